#include "fem/contact_assembly.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "fem/stress_extrapolation.hpp"

namespace ifsim::fem {

MortarContact2D::MortarContact2D(const Mesh& mesh, const std::string& slave_faces,
                                 const std::string& master_faces)
    : slave_(mesh, slave_faces), master_(mesh, master_faces) {}

bool MortarContact2D::pair(const Mesh& mesh, const std::vector<double>& u) {
    slave_.set_configuration(mesh, &u);
    master_.set_configuration(mesh, &u);
    const auto gauss = slave_.integration_points();
    bool changed = gauss.size() != points_.size();
    std::vector<ContactPointState> next(gauss.size());
    for (std::size_t i = 0; i < gauss.size(); ++i) {
        ContactPointState& p = next[i];
        p.slave = gauss[i];
        // Start from the previous master edge: the projection walks from there (Eq. A9).
        const int start = changed ? -1 : points_[i].master.edge;
        p.master = master_.project(p.slave.x, start);
        if (p.master.in_contact) {
            p.g_N0 = normal_gap(p.master, p.slave.x);
        }
        p.g_N = p.g_N0;
        if (!changed) {
            changed = p.master.in_contact != points_[i].master.in_contact ||
                      p.master.edge != points_[i].master.edge;
        }
    }
    points_ = std::move(next);
    view_.resize(points_.size());
    ++counters_.pairings;
    counters_.projections += static_cast<long>(points_.size());
    for (std::size_t i = 0; i < points_.size(); ++i) {
        counters_.projection_iterations += points_[i].master.iterations;
        refresh_view(i);
    }
    counters_.pattern_changes += changed ? 1 : 0;
    return changed;
}

void MortarContact2D::refresh_view(std::size_t i) {
    const ContactPointState& p = points_[i];
    ContactKinematics& v = view_[i];
    v.active = p.master.in_contact;
    v.g_N = p.g_N;
    v.dg_T = {p.dg_T, 0.0};
    v.n = {p.master.normal[0], p.master.normal[1], 0.0};
    v.t1 = {p.master.tangent[0], p.master.tangent[1], 0.0};
    v.t2 = {0.0, 0.0, 1.0};
    const FaceRef& face = slave_.edge_face(p.slave.edge);
    v.slave_element = face.element;
    const auto xi = quad4_face_point(face.local_face, p.slave.xi);
    v.slave_natural = {xi[0], xi[1], 0.0};
    v.weight = p.slave.weight_j;
    v.x = {p.slave.x[0], p.slave.x[1], 0.0};
}

void MortarContact2D::update_gaps(const std::vector<double>& du) {
    for (auto& p : points_) {
        if (!p.master.in_contact) {
            continue;
        }
        std::array<double, 2> dus{};
        std::array<double, 2> dum{};
        for (std::size_t d = 0; d < 2; ++d) {
            for (std::size_t a = 0; a < 2; ++a) {
                dus[d] += p.slave.N[a] * du[static_cast<std::size_t>(2 * p.slave.nodes[a]) + d];
                dum[d] += p.master.N[a] * du[static_cast<std::size_t>(2 * p.master.nodes[a]) + d];
            }
        }
        p.g_N = p.g_N0 + (dus[0] - dum[0]) * p.master.normal[0] +
                (dus[1] - dum[1]) * p.master.normal[1];
        p.dg_T = tangential_gap_increment(p.master, du, dus); // Eq. A13
    }
    for (std::size_t i = 0; i < points_.size(); ++i) {
        view_[i].g_N = points_[i].g_N;
        view_[i].dg_T[0] = points_[i].dg_T;
    }
}

void MortarContact2D::assemble(std::span<const ContactTraction> traction,
                               std::vector<double>& f_int, std::vector<ContactTriplet>* K) const {
    if (traction.size() != points_.size()) {
        throw std::invalid_argument("MortarContact2D::assemble: one traction per contact point");
    }
    std::vector<PointTraction> planar(traction.size());
    for (std::size_t i = 0; i < traction.size(); ++i) {
        planar[i].t_N = traction[i].t_N;
        planar[i].tau = traction[i].tau[0];
        for (std::size_t c = 0; c < 4; ++c) { // slave x, y, master x, y
            planar[i].jac[0][c] = traction[i].jac[0][c];
            planar[i].jac[1][c] = traction[i].jac[1][c];
        }
    }
    assemble(std::span<const PointTraction>(planar), f_int, K);
}

void MortarContact2D::assemble(std::span<const PointTraction> traction, std::vector<double>& f_int,
                               std::vector<ContactTriplet>* K) const {
    if (traction.size() != points_.size()) {
        throw std::invalid_argument("MortarContact2D::assemble: one traction per contact point");
    }
    for (std::size_t i = 0; i < points_.size(); ++i) {
        const auto& p = points_[i];
        if (!p.master.in_contact) {
            continue;
        }
        const auto& tr = traction[i];
        const auto& n = p.master.normal;
        const auto& t = p.master.tangent;
        const double wj = p.slave.weight_j;
        // Nodes of the point: the slave edge (sign +1) and the master edge (sign -1), with the
        // shape function of each at the point (Eqs. A20, A21).
        const int node[4] = {p.slave.nodes[0], p.slave.nodes[1], p.master.nodes[0],
                             p.master.nodes[1]};
        const double N[4] = {p.slave.N[0], p.slave.N[1], -p.master.N[0], -p.master.N[1]};
        for (int a = 0; a < 4; ++a) {
            for (std::size_t d = 0; d < 2; ++d) {
                f_int[static_cast<std::size_t>(2 * node[a]) + d] +=
                    N[a] * (tr.t_N * n[d] - tr.tau * t[d]) * wj;
            }
        }
        if (K == nullptr) {
            continue;
        }
        // d f_a / d u_b: the point's displacement is sum N_b u_b on either side, so the
        // Jacobian column of side s (0 slave, 1 master) is weighted by |N_b|.
        for (int a = 0; a < 4; ++a) {
            for (int b = 0; b < 4; ++b) {
                const int side = b < 2 ? 0 : 1;
                const double Nb = std::abs(N[b]);
                for (int d = 0; d < 2; ++d) {
                    for (int e = 0; e < 2; ++e) {
                        const double dtN = tr.jac[0][static_cast<std::size_t>(2 * side + e)];
                        const double dtau = tr.jac[1][static_cast<std::size_t>(2 * side + e)];
                        const double v = N[a] *
                                         (dtN * n[static_cast<std::size_t>(d)] -
                                          dtau * t[static_cast<std::size_t>(d)]) *
                                         Nb * wj;
                        if (v != 0.0) {
                            K->push_back({2 * node[a] + d, 2 * node[b] + e, v});
                        }
                    }
                }
            }
        }
    }
}

std::vector<std::array<int, 2>> MortarContact2D::couplings() const {
    std::vector<std::array<int, 2>> c;
    for (const auto& p : points_) {
        if (!p.master.in_contact) {
            continue;
        }
        const int node[4] = {p.slave.nodes[0], p.slave.nodes[1], p.master.nodes[0],
                             p.master.nodes[1]};
        for (int a : node) {
            for (int b : node) {
                for (int d = 0; d < 2; ++d) {
                    for (int e = 0; e < 2; ++e) {
                        c.push_back({2 * a + d, 2 * b + e});
                    }
                }
            }
        }
    }
    std::sort(c.begin(), c.end());
    c.erase(std::unique(c.begin(), c.end()), c.end());
    return c;
}

} // namespace ifsim::fem
