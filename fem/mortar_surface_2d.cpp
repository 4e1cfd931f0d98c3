#include "fem/mortar_surface_2d.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

namespace ifsim::fem {

namespace {

using V2 = std::array<double, 2>;

V2 unit(V2 v) {
    const double l = std::hypot(v[0], v[1]);
    return {v[0] / l, v[1] / l};
}

double dot(const V2& a, const V2& b) {
    return a[0] * b[0] + a[1] * b[1];
}

} // namespace

MortarSurface2D::MortarSurface2D(const Mesh& mesh, const std::string& face_set) {
    if (mesh.dim() != 2) {
        throw std::invalid_argument("MortarSurface2D: the mesh must be 2D (quad4)");
    }
    const auto& faces = mesh.face_set(face_set);
    if (faces.empty()) {
        throw std::invalid_argument("MortarSurface2D: face set '" + face_set + "' is empty");
    }
    for (const FaceRef& f : faces) {
        const auto local = face_nodes(mesh.type, f.local_face);
        edges_.push_back({mesh.node(f.element, local[0]), mesh.node(f.element, local[1])});
        faces_.push_back(f);
    }
    // Neighbours: the end node of one edge is the start node of the next (consistent
    // orientation along the boundary of the body).
    std::map<int, int> starting_at;
    for (std::size_t e = 0; e < edges_.size(); ++e) {
        starting_at[edges_[e][0]] = static_cast<int>(e);
    }
    next_.assign(edges_.size(), -1);
    prev_.assign(edges_.size(), -1);
    for (std::size_t e = 0; e < edges_.size(); ++e) {
        const auto it = starting_at.find(edges_[e][1]);
        if (it != starting_at.end()) {
            next_[e] = it->second;
            prev_[static_cast<std::size_t>(it->second)] = static_cast<int>(e);
        }
    }
    set_configuration(mesh, nullptr);
}

void MortarSurface2D::set_configuration(const Mesh& mesh, const std::vector<double>* u) {
    x_ = mesh.coordinates;
    if (u != nullptr) {
        for (std::size_t i = 0; i < x_.size(); ++i) {
            x_[i] += (*u)[i];
        }
    }
}

V2 MortarSurface2D::node_x(int node) const {
    return {x_[static_cast<std::size_t>(2 * node)], x_[static_cast<std::size_t>(2 * node + 1)]};
}

// Averaged unit tangent at end `end` (0 start, 1 end) of edge e: the mean of the unit tangents
// of the edges sharing the node (one edge at a chain end).
V2 MortarSurface2D::nodal_tangent(int e, int end) const {
    const auto& n = edges_[static_cast<std::size_t>(e)];
    V2 t = unit({node_x(n[1])[0] - node_x(n[0])[0], node_x(n[1])[1] - node_x(n[0])[1]});
    const int other =
        end == 0 ? prev_[static_cast<std::size_t>(e)] : next_[static_cast<std::size_t>(e)];
    if (other >= 0) {
        const auto& m = edges_[static_cast<std::size_t>(other)];
        const V2 s = unit({node_x(m[1])[0] - node_x(m[0])[0], node_x(m[1])[1] - node_x(m[0])[1]});
        t = unit({t[0] + s[0], t[1] + s[1]});
    }
    return t;
}

SurfaceProjection MortarSurface2D::project(const V2& p, int start) const {
    SurfaceProjection r;
    int e = start;
    if (e < 0) { // nearest edge by the clamped segment projection
        double best = std::numeric_limits<double>::max();
        for (int k = 0; k < n_edges(); ++k) {
            const V2 a = node_x(edges_[static_cast<std::size_t>(k)][0]);
            const V2 b = node_x(edges_[static_cast<std::size_t>(k)][1]);
            const V2 ab{b[0] - a[0], b[1] - a[1]};
            double s = dot({p[0] - a[0], p[1] - a[1]}, ab) / dot(ab, ab);
            s = std::clamp(s, 0.0, 1.0);
            const double d = std::hypot(a[0] + s * ab[0] - p[0], a[1] + s * ab[1] - p[1]);
            if (d < best) {
                best = d;
                e = k;
            }
        }
    }
    // The smoothed residual R (Eq. A9) is continuous along the chain (x and the nodal
    // tangents are shared at nodes), so its end values decide where the root lies: R(1) < 0
    // means the point lies beyond the edge's end, R(-1) > 0 before its start. Inside a
    // bracketing edge, Newton (Eq. A10 plus the slope of the smoothed tangent) with a bisection
    // safeguard: far from the surface the tangent's slope can make K change sign.
    constexpr double tol = 1e-13;
    for (int visits = 0; visits <= n_edges(); ++visits) {
        const auto& n = edges_[static_cast<std::size_t>(e)];
        const V2 xa = node_x(n[0]);
        const V2 xb = node_x(n[1]);
        const V2 ta = nodal_tangent(e, 0);
        const V2 tb = nodal_tangent(e, 1);
        const V2 x_xi{0.5 * (xb[0] - xa[0]), 0.5 * (xb[1] - xa[1])};
        const V2 dt{0.5 * (tb[0] - ta[0]), 0.5 * (tb[1] - ta[1])};
        const double scale = dot(x_xi, x_xi);
        auto residual = [&](double xi, double* K) {
            const double N0 = 0.5 * (1.0 - xi);
            const double N1 = 0.5 * (1.0 + xi);
            const V2 g{N0 * xa[0] + N1 * xb[0] - p[0], N0 * xa[1] + N1 * xb[1] - p[1]};
            const V2 t{N0 * ta[0] + N1 * tb[0], N0 * ta[1] + N1 * tb[1]};
            *K = dot(x_xi, t) + dot(g, dt);
            return dot(g, t);
        };
        double K = 0.0;
        const double r_lo = residual(-1.0, &K);
        const double r_hi = residual(1.0, &K);
        const double slack = tol * scale;
        if (r_hi < -slack || r_lo > slack) {
            const int to = r_hi < -slack ? next_[static_cast<std::size_t>(e)]
                                         : prev_[static_cast<std::size_t>(e)];
            if (r_hi < -slack && r_lo > slack) {
                return r; // residual decreasing through the edge: a distance maximum
            }
            if (to < 0) {
                return r; // natural border: not in contact
            }
            e = to;
            continue;
        }
        double lo = -1.0;
        double hi = 1.0;
        double xi = std::abs(r_hi - r_lo) > 0.0
                        ? std::clamp(-1.0 - 2.0 * r_lo / (r_hi - r_lo), -1.0, 1.0)
                        : 0.0;
        for (int it = 0; it < 60; ++it) {
            ++r.iterations;
            const double R = residual(xi, &K);
            if (std::abs(R) <= slack) {
                break;
            }
            (R < 0.0 ? lo : hi) = xi;
            double next = K > 0.0 ? xi - R / K : 0.5 * (lo + hi);
            if (!(next > lo && next < hi)) {
                next = 0.5 * (lo + hi);
            }
            if (std::abs(next - xi) < 1e-15) {
                xi = next;
                break;
            }
            xi = next;
        }
        const double N0 = 0.5 * (1.0 - xi);
        const double N1 = 0.5 * (1.0 + xi);
        const V2 t = unit({N0 * ta[0] + N1 * tb[0], N0 * ta[1] + N1 * tb[1]});
        r.in_contact = true;
        r.edge = e;
        r.xi = xi;
        r.N = {N0, N1};
        r.nodes = n;
        r.x = {N0 * xa[0] + N1 * xb[0], N0 * xa[1] + N1 * xb[1]};
        r.tangent = t;
        r.normal = {t[1], -t[0]};
        return r;
    }
    return r;
}

std::vector<SlavePoint> MortarSurface2D::integration_points() const {
    std::vector<SlavePoint> pts;
    const double g = 1.0 / std::sqrt(3.0);
    for (int e = 0; e < n_edges(); ++e) {
        const auto& n = edges_[static_cast<std::size_t>(e)];
        const V2 xa = node_x(n[0]);
        const V2 xb = node_x(n[1]);
        const double half = 0.5 * std::hypot(xb[0] - xa[0], xb[1] - xa[1]);
        for (const double xi : {-g, g}) {
            SlavePoint s;
            s.edge = e;
            s.xi = xi;
            s.N = {0.5 * (1.0 - xi), 0.5 * (1.0 + xi)};
            s.nodes = n;
            s.weight_j = half;
            s.x = {s.N[0] * xa[0] + s.N[1] * xb[0], s.N[0] * xa[1] + s.N[1] * xb[1]};
            pts.push_back(s);
        }
    }
    return pts;
}

double normal_gap(const SurfaceProjection& m, const std::array<double, 2>& slave_x) {
    return (slave_x[0] - m.x[0]) * m.normal[0] + (slave_x[1] - m.x[1]) * m.normal[1];
}

double tangential_gap_increment(const SurfaceProjection& m, const std::vector<double>& du,
                                const std::array<double, 2>& slave_du) {
    double d = 0.0;
    for (int i = 0; i < 2; ++i) {
        const double master = m.N[0] * du[static_cast<std::size_t>(2 * m.nodes[0] + i)] +
                              m.N[1] * du[static_cast<std::size_t>(2 * m.nodes[1] + i)];
        d += (master - slave_du[static_cast<std::size_t>(i)]) *
             m.tangent[static_cast<std::size_t>(i)];
    }
    return d;
}

} // namespace ifsim::fem
