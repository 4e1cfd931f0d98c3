// Longer than 400 lines on purpose: the surface set-up (neighbours, smoothed nodal normals)
// and the projection (Newton on a bilinear face, crossing to the neighbour across an edge,
// the nearest-face start) are one algorithm whose pieces share the face geometry below;
// split, each part would need the others' internals.
#include "fem/mortar_surface_3d.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <utility>

#include "fem/shape_functions.hpp"

namespace ifsim::fem {

namespace {

using V2 = std::array<double, 2>;

// Natural coordinates of the corners of a face in face_nodes() order.
constexpr double corner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};

double dot(const Vec3& a, const Vec3& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Vec3 axpy(double s, const Vec3& a, const Vec3& b) { // s a + b
    return {s * a[0] + b[0], s * a[1] + b[1], s * a[2] + b[2]};
}
double norm(const Vec3& a) {
    return std::sqrt(dot(a, a));
}
Vec3 unit(const Vec3& a) {
    const double l = norm(a);
    return {a[0] / l, a[1] / l, a[2] / l};
}

} // namespace

// Position, tangents and smoothed normal of a face with their xi-derivatives.
struct MortarSurface3D::Local {
    std::array<double, 4> N{};
    Vec3 x{}, a1{}, a2{}, a12{}; // x, x_xi1, x_xi2, x_xi1xi2 (bilinear: x_xi1xi1 = 0)
    Vec3 n{}, n1{}, n2{};        // smoothed unit normal and its xi-derivatives
};

MortarSurface3D::MortarSurface3D(const Mesh& mesh, const std::string& face_set) {
    if (mesh.dim() != 3) {
        throw std::invalid_argument("MortarSurface3D: the mesh must be 3D (hex8)");
    }
    const auto& faces = mesh.face_set(face_set);
    if (faces.empty()) {
        throw std::invalid_argument("MortarSurface3D: face set '" + face_set + "' is empty");
    }
    surface_index_.assign(static_cast<std::size_t>(mesh.n_nodes()), -1);
    int n_surface = 0;
    for (const FaceRef& f : faces) {
        const auto local = face_nodes(mesh.type, f.local_face);
        std::array<int, 4> nodes{};
        std::array<int, 4> sn{};
        for (std::size_t c = 0; c < 4; ++c) {
            nodes[c] = mesh.node(f.element, local[c]);
            int& s = surface_index_[static_cast<std::size_t>(nodes[c])];
            if (s < 0) {
                s = n_surface++;
            }
            sn[c] = s;
        }
        faces_.push_back(nodes);
        face_sn_.push_back(sn);
        refs_.push_back(f);
    }
    // Adjacency through shared edges (an unordered node pair names an edge).
    std::map<std::pair<int, int>, std::vector<std::pair<int, int>>> edges;
    for (std::size_t f = 0; f < faces_.size(); ++f) {
        for (int k = 0; k < 4; ++k) {
            const int a = faces_[f][static_cast<std::size_t>(k)];
            const int b = faces_[f][static_cast<std::size_t>((k + 1) % 4)];
            edges[{std::min(a, b), std::max(a, b)}].push_back({static_cast<int>(f), k});
        }
    }
    neighbours_.assign(faces_.size(), {-1, -1, -1, -1});
    for (const auto& [key, sharing] : edges) {
        if (sharing.size() < 2) {
            continue; // free border
        }
        // Manifold surfaces share an edge between two faces; otherwise the first two.
        const auto [f0, k0] = sharing[0];
        const auto [f1, k1] = sharing[1];
        neighbours_[static_cast<std::size_t>(f0)][static_cast<std::size_t>(k0)] = f1;
        neighbours_[static_cast<std::size_t>(f1)][static_cast<std::size_t>(k1)] = f0;
    }
    nodal_normal_.resize(static_cast<std::size_t>(n_surface));
    set_configuration(mesh, nullptr);
}

Vec3 MortarSurface3D::node_x(int node) const {
    const auto i = static_cast<std::size_t>(3 * node);
    return {x_[i], x_[i + 1], x_[i + 2]};
}

void MortarSurface3D::set_configuration(const Mesh& mesh, const std::vector<double>* u) {
    x_ = mesh.coordinates;
    if (u != nullptr) {
        for (std::size_t i = 0; i < x_.size(); ++i) {
            x_[i] += (*u)[i];
        }
    }
    // Nodal normals: mean of the unit normals of the faces meeting at the node, each taken at
    // its corner (x_xi1 x x_xi2 there).
    std::fill(nodal_normal_.begin(), nodal_normal_.end(), Vec3{});
    for (std::size_t f = 0; f < faces_.size(); ++f) {
        for (std::size_t c = 0; c < 4; ++c) {
            const Vec3 x0 = node_x(faces_[f][c]);
            // Corner c's edges along xi1 and xi2 (to the corner differing in that coordinate).
            const std::size_t c1 = c ^ 1U; // 0<->1, 2<->3: xi1 differs
            const std::size_t c2 = 3 - c;  // 0<->3, 1<->2: xi2 differs
            const Vec3 e1 = axpy(-1.0, x0, node_x(faces_[f][c1]));
            const Vec3 e2 = axpy(-1.0, x0, node_x(faces_[f][c2]));
            const double s = corner[c1][0] - corner[c][0] > 0 ? 1.0 : -1.0;
            const double t = corner[c2][1] - corner[c][1] > 0 ? 1.0 : -1.0;
            const Vec3 nf = unit(cross(e1, e2));
            Vec3& acc = nodal_normal_[static_cast<std::size_t>(face_sn_[f][c])];
            acc = axpy(s * t, nf, acc);
        }
    }
    for (Vec3& n : nodal_normal_) {
        n = unit(n);
    }
}

MortarSurface3D::Local MortarSurface3D::evaluate(int f, const V2& xi) const {
    Local L;
    Vec3 m{}, m1{}, m2{};
    const auto fi = static_cast<std::size_t>(f);
    for (std::size_t c = 0; c < 4; ++c) {
        const double s = corner[c][0];
        const double t = corner[c][1];
        const double N = 0.25 * (1.0 + s * xi[0]) * (1.0 + t * xi[1]);
        const double N1 = 0.25 * s * (1.0 + t * xi[1]);
        const double N2 = 0.25 * t * (1.0 + s * xi[0]);
        const double N12 = 0.25 * s * t;
        const Vec3 X = node_x(faces_[fi][c]);
        const Vec3& mn = nodal_normal_[static_cast<std::size_t>(face_sn_[fi][c])];
        L.N[c] = N;
        L.x = axpy(N, X, L.x);
        L.a1 = axpy(N1, X, L.a1);
        L.a2 = axpy(N2, X, L.a2);
        L.a12 = axpy(N12, X, L.a12);
        m = axpy(N, mn, m);
        m1 = axpy(N1, mn, m1);
        m2 = axpy(N2, mn, m2);
    }
    const double lm = norm(m);
    if (!(lm > 1e-8)) { // opposite nodal normals: fall back to the face's own normal
        L.n = unit(cross(L.a1, L.a2));
        return L;
    }
    L.n = {m[0] / lm, m[1] / lm, m[2] / lm};
    // d(m/|m|) = (I - n n) dm / |m|
    L.n1 = axpy(-dot(L.n, m1) / lm, L.n, {m1[0] / lm, m1[1] / lm, m1[2] / lm});
    L.n2 = axpy(-dot(L.n, m2) / lm, L.n, {m2[0] / lm, m2[1] / lm, m2[2] / lm});
    return L;
}

Vec3 MortarSurface3D::smoothed_normal(int f, const V2& xi) const {
    return evaluate(f, xi).n;
}

int MortarSurface3D::nearest_face(const Vec3& p, V2& xi) const {
    // Sampled distance (3x3 interior points per face): only a start for the walk.
    double best = std::numeric_limits<double>::max();
    int face = 0;
    constexpr double s[3] = {-0.75, 0.0, 0.75};
    for (int f = 0; f < n_faces(); ++f) {
        for (double s1 : s) {
            for (double s2 : s) {
                Vec3 x{};
                for (std::size_t c = 0; c < 4; ++c) {
                    const double N = 0.25 * (1.0 + corner[c][0] * s1) * (1.0 + corner[c][1] * s2);
                    x = axpy(N, node_x(faces_[static_cast<std::size_t>(f)][c]), x);
                }
                const double d = norm(axpy(-1.0, p, x));
                if (d < best) {
                    best = d;
                    face = f;
                    xi = {s1, s2};
                }
            }
        }
    }
    return face;
}

// The point xi on edge k of face f expressed in the coordinates of the neighbour g.
V2 MortarSurface3D::across(int f, int k, const V2& xi, int g) const {
    const auto& F = faces_[static_cast<std::size_t>(f)];
    const auto& G = faces_[static_cast<std::size_t>(g)];
    const std::size_t k0 = static_cast<std::size_t>(k);
    const std::size_t k1 = (k0 + 1) % 4;
    // Edge parameter lambda in [0, 1] from corner k to corner k+1 (|corner difference| = 2).
    const double lambda = 0.25 * ((xi[0] - corner[k0][0]) * (corner[k1][0] - corner[k0][0]) +
                                  (xi[1] - corner[k0][1]) * (corner[k1][1] - corner[k0][1]));
    for (std::size_t j0 = 0; j0 < 4; ++j0) {
        const std::size_t j1 = (j0 + 1) % 4;
        double l = -1.0;
        if (G[j0] == F[k1] && G[j1] == F[k0]) {
            l = 1.0 - lambda; // consistent orientation: the edge runs the other way
        } else if (G[j0] == F[k0] && G[j1] == F[k1]) {
            l = lambda;
        }
        if (l >= 0.0) {
            return {corner[j0][0] + l * (corner[j1][0] - corner[j0][0]),
                    corner[j0][1] + l * (corner[j1][1] - corner[j0][1])};
        }
    }
    return {0.0, 0.0}; // unreachable for faces built as neighbours
}

// Newton step on xi for the residual R_a = x_xia . (I - n n)(x - p) (Eqs. A15, A16 with the
// tangent plane of the smoothed normal; zero iff x - p is along n), with the exact slope of
// the smoothed normal (Eq. A17). Where that Jacobian is not positive (far from a strongly
// curved surface) the Gauss-Newton matrix (P x_xia) . (P x_xib) keeps the step a descent one.
// At most half a face per step.
std::array<double, 2> MortarSurface3D::newton_step(const Local& L, const Vec3& p, bool& converged) {
    constexpr double tol = 1e-13;
    const Vec3 g = axpy(-1.0, p, L.x);
    const double ng = dot(L.n, g);
    const Vec3* a[2] = {&L.a1, &L.a2};
    const Vec3* dn[2] = {&L.n1, &L.n2};
    double R[2];
    double J[2][2];
    double G[2][2];
    for (int al = 0; al < 2; ++al) {
        const double an = dot(*a[al], L.n);
        R[al] = dot(*a[al], g) - an * ng;
        for (int be = 0; be < 2; ++be) {
            const Vec3 aab = al == be ? Vec3{} : L.a12; // x_xi_a xi_b
            const double aa = dot(*a[al], *a[be]);
            G[al][be] = aa - an * dot(*a[be], L.n);
            J[al][be] = dot(aab, g) + aa - (dot(aab, L.n) + dot(*a[al], *dn[be])) * ng -
                        an * (dot(*dn[be], g) + dot(L.n, *a[be]));
        }
    }
    const double scale = dot(L.a1, L.a1) + dot(L.a2, L.a2);
    converged = std::hypot(R[0], R[1]) <= tol * scale;
    if (converged) {
        return {0.0, 0.0};
    }
    double det = J[0][0] * J[1][1] - J[0][1] * J[1][0];
    const double(*K)[2] = J;
    if (!(det > 1e-12 * scale * scale) || J[0][0] + J[1][1] <= 0.0) {
        K = G;
        det = G[0][0] * G[1][1] - G[0][1] * G[1][0];
    }
    V2 d{-(K[1][1] * R[0] - K[0][1] * R[1]) / det, -(-K[1][0] * R[0] + K[0][0] * R[1]) / det};
    const double big = std::max(std::abs(d[0]), std::abs(d[1]));
    if (big > 1.0) {
        d = {d[0] / big, d[1] / big};
    }
    return d;
}

SurfaceProjection3D MortarSurface3D::project(const Vec3& p, int start) const {
    SurfaceProjection3D r;
    V2 xi{0.0, 0.0};
    int f = start;
    if (f < 0) {
        f = nearest_face(p, xi);
    }
    // Newton steps stop on a face's edge; pushing further out crosses to the neighbour (or,
    // at the free border, ends the projection). A step pushing straight back across the edge
    // just crossed (the root lies on the edge within rounding) is clamped to the edge. An
    // iteration limit ends the walk at the last iterate.
    constexpr double on_edge = 1e-12;
    const int max_iterations = 60 + 8 * n_faces();
    int entered = -1;  // edge of f through which the walk entered it
    bool moved = true; // xi changed since entering f
    int pinned = -1;   // edge of f on which the iterate is held (root on the edge)
    for (int it = 0; it < max_iterations; ++it) {
        ++r.iterations;
        bool converged = false;
        const V2 d = newton_step(evaluate(f, xi), p, converged);
        // Edges the step crosses (edge 0 xi2 = -1, 1 xi1 = 1, 2 xi2 = 1, 3 xi1 = -1) and the
        // step fraction t at which it does.
        std::array<double, 4> t_cross{2.0, 2.0, 2.0, 2.0};
        double t_exit = 2.0;
        for (std::size_t k = 0; k < 4; ++k) {
            const std::size_t c = (k % 2 == 0) ? 1 : 0;
            const double bound = (k == 0 || k == 3) ? -1.0 : 1.0;
            const double target = xi[c] + d[c];
            if ((bound > 0.0 && target > bound) || (bound < 0.0 && target < bound)) {
                t_cross[k] = std::max(0.0, (bound - xi[c]) / d[c]);
                t_exit = std::min(t_exit, t_cross[k]);
            }
        }
        // Of the edges crossed first (a corner: two), prefer one leading to a new face, then
        // the free border, last the edge just entered through.
        int k_exit = -1;
        int best_rank = 3;
        for (int k = 0; k < 4; ++k) {
            const double t = t_cross[static_cast<std::size_t>(k)];
            if (t > 1.0 || t > t_exit + on_edge) { // not crossed, or crossed later
                continue;
            }
            const bool back = k == pinned || (k == entered && !moved);
            const int rank = back ? 2 : (neighbour(f, k) < 0 ? 1 : 0);
            if (rank < best_rank) {
                best_rank = rank;
                k_exit = k;
            }
        }
        if (k_exit >= 0 && t_exit <= on_edge && k_exit != pinned) {
            // On the edge and pushing out: cross, or stop at the free border.
            const int nb = neighbour(f, k_exit);
            if (nb < 0) {
                return r; // natural border: not in contact
            }
            if (k_exit == entered && !moved) {
                pinned = k_exit; // pushed back across the edge just crossed
            } else {
                const V2 next = across(f, k_exit, xi, nb);
                int back = -1;
                for (int j = 0; j < 4; ++j) {
                    if (neighbour(nb, j) == f) {
                        back = j;
                    }
                }
                f = nb;
                xi = next;
                entered = back;
                moved = false;
                pinned = -1;
                continue;
            }
        }
        V2 next{xi[0] + d[0], xi[1] + d[1]};
        if (k_exit >= 0 && k_exit != pinned) {
            next = {xi[0] + t_exit * d[0], xi[1] + t_exit * d[1]}; // stop on the edge first
        }
        next = {std::clamp(next[0], -1.0, 1.0), std::clamp(next[1], -1.0, 1.0)};
        const double step = std::max(std::abs(next[0] - xi[0]), std::abs(next[1] - xi[1]));
        if (step > 1e-15) {
            moved = true;
        }
        xi = next;
        if (converged || step < 1e-14) {
            break;
        }
    }
    const Local L = evaluate(f, xi);
    r.in_contact = true;
    r.face = f;
    r.xi = xi;
    r.N = L.N;
    r.nodes = faces_[static_cast<std::size_t>(f)];
    r.x = L.x;
    r.normal = L.n;
    r.t1 = unit(axpy(-dot(L.a1, L.n), L.n, L.a1));
    r.t2 = cross(r.normal, r.t1);
    return r;
}

std::vector<SlavePoint3D> MortarSurface3D::integration_points() const {
    std::vector<SlavePoint3D> pts;
    pts.reserve(4 * faces_.size());
    const double g = 1.0 / std::sqrt(3.0);
    for (int f = 0; f < n_faces(); ++f) {
        for (const double s2 : {-g, g}) {
            for (const double s1 : {-g, g}) {
                const Local L = evaluate(f, {s1, s2});
                SlavePoint3D s;
                s.face = f;
                s.xi = {s1, s2};
                s.N = L.N;
                s.nodes = faces_[static_cast<std::size_t>(f)];
                s.weight_j = norm(cross(L.a1, L.a2)); // Gauss weight 1
                s.x = L.x;
                s.natural = hex8_face_point(refs_[static_cast<std::size_t>(f)].local_face, s.xi);
                pts.push_back(s);
            }
        }
    }
    return pts;
}

Vec3 hex8_face_point(int local_face, const V2& s) {
    const auto nodes = face_nodes(ElementType::hex8, local_face);
    Vec3 xi{};
    for (std::size_t c = 0; c < 4; ++c) {
        const double N = 0.25 * (1.0 + corner[c][0] * s[0]) * (1.0 + corner[c][1] * s[1]);
        const auto& X = Shape<ElementType::hex8>::node_xi[nodes[c]];
        xi = axpy(N, {X[0], X[1], X[2]}, xi);
    }
    return xi;
}

double normal_gap(const SurfaceProjection3D& m, const Vec3& slave_x) {
    return dot(axpy(-1.0, m.x, slave_x), m.normal);
}

std::array<double, 2> tangential_gap_increments(const SurfaceProjection3D& m,
                                                const std::vector<double>& du,
                                                const Vec3& slave_du) {
    Vec3 rel{-slave_du[0], -slave_du[1], -slave_du[2]};
    for (std::size_t c = 0; c < 4; ++c) {
        const auto i = static_cast<std::size_t>(3 * m.nodes[c]);
        rel = axpy(m.N[c], {du[i], du[i + 1], du[i + 2]}, rel);
    }
    return {dot(rel, m.t1), dot(rel, m.t2)};
}

} // namespace ifsim::fem
