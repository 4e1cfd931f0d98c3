#include "fem/contact_assembly_3d.hpp"

#include <algorithm>
#include <stdexcept>

namespace ifsim::fem {

MortarContact3D::MortarContact3D(const Mesh& mesh, const std::string& slave_faces,
                                 const std::string& master_faces)
    : slave_(mesh, slave_faces), master_(mesh, master_faces) {}

bool MortarContact3D::pair(const Mesh& mesh, const std::vector<double>& u) {
    slave_.set_configuration(mesh, &u);
    master_.set_configuration(mesh, &u);
    const auto gauss = slave_.integration_points();
    const bool same_points = gauss.size() == points_.size();
    bool changed = !same_points;
    std::vector<ContactPointState3D> next(gauss.size());
    for (std::size_t i = 0; i < gauss.size(); ++i) {
        ContactPointState3D& p = next[i];
        p.slave = gauss[i];
        // Start from the previous master face (-1 when inactive: the nearest); the projection
        // walks from there.
        const int start = same_points ? points_[i].master.face : -1;
        p.master = master_.project(p.slave.x, start);
        if (p.master.in_contact) {
            p.g_N0 = normal_gap(p.master, p.slave.x);
        }
        p.g_N = p.g_N0;
        if (!changed) {
            changed = p.master.in_contact != points_[i].master.in_contact ||
                      p.master.face != points_[i].master.face;
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

void MortarContact3D::refresh_view(std::size_t i) {
    const ContactPointState3D& p = points_[i];
    ContactKinematics& v = view_[i];
    v.active = p.master.in_contact;
    v.g_N = p.g_N;
    v.dg_T = p.dg_T;
    v.n = p.master.normal;
    v.t1 = p.master.t1;
    v.t2 = p.master.t2;
    v.slave_element = slave_.face_ref(p.slave.face).element;
    v.slave_natural = p.slave.natural;
    v.weight = p.slave.weight_j;
    v.x = p.slave.x;
}

void MortarContact3D::update_gaps(const std::vector<double>& du) {
    for (std::size_t i = 0; i < points_.size(); ++i) {
        ContactPointState3D& p = points_[i];
        if (!p.master.in_contact) {
            continue;
        }
        Vec3 dus{};
        Vec3 dum{};
        for (std::size_t d = 0; d < 3; ++d) {
            for (std::size_t a = 0; a < 4; ++a) {
                dus[d] += p.slave.N[a] * du[static_cast<std::size_t>(3 * p.slave.nodes[a]) + d];
                dum[d] += p.master.N[a] * du[static_cast<std::size_t>(3 * p.master.nodes[a]) + d];
            }
        }
        p.g_N = p.g_N0;
        p.dg_T = {0.0, 0.0};
        for (std::size_t d = 0; d < 3; ++d) {
            p.g_N += (dus[d] - dum[d]) * p.master.normal[d];
            p.dg_T[0] += (dum[d] - dus[d]) * p.master.t1[d]; // Eq. A13
            p.dg_T[1] += (dum[d] - dus[d]) * p.master.t2[d];
        }
        view_[i].g_N = p.g_N;
        view_[i].dg_T = p.dg_T;
    }
}

void MortarContact3D::assemble(std::span<const ContactTraction> traction,
                               std::vector<double>& f_int, std::vector<ContactTriplet>* K) const {
    if (traction.size() != points_.size()) {
        throw std::invalid_argument("MortarContact3D::assemble: one traction per contact point");
    }
    for (std::size_t i = 0; i < points_.size(); ++i) {
        const ContactPointState3D& p = points_[i];
        if (!p.master.in_contact) {
            continue;
        }
        const ContactTraction& tr = traction[i];
        const Vec3& n = p.master.normal;
        const Vec3& t1 = p.master.t1;
        const Vec3& t2 = p.master.t2;
        const double wj = p.slave.weight_j;
        // Nodes of the point: the slave face (sign +1) and the master face (sign -1), with the
        // shape function of each at the point (Eqs. A20, A21).
        std::array<int, 8> node{};
        std::array<double, 8> N{};    // signed: the master side carries the reaction
        std::array<double, 8> Nabs{}; // weight of the node in its side's point displacement
        for (std::size_t a = 0; a < 4; ++a) {
            node[a] = p.slave.nodes[a];
            node[a + 4] = p.master.nodes[a];
            N[a] = p.slave.N[a];
            N[a + 4] = -p.master.N[a];
            Nabs[a] = p.slave.N[a];
            Nabs[a + 4] = p.master.N[a];
        }
        Vec3 t{}; // traction vector on the slave (internal-force sense)
        for (std::size_t d = 0; d < 3; ++d) {
            t[d] = (tr.t_N * n[d] - tr.tau[0] * t1[d] - tr.tau[1] * t2[d]) * wj;
        }
        for (std::size_t a = 0; a < 8; ++a) {
            for (std::size_t d = 0; d < 3; ++d) {
                f_int[static_cast<std::size_t>(3 * node[a]) + d] += N[a] * t[d];
            }
        }
        if (K == nullptr) {
            continue;
        }
        // d t / d u_side,e for both sides (columns [0,3) slave, [3,6) master of tr.jac).
        std::array<std::array<double, 6>, 3> dt{};
        for (std::size_t d = 0; d < 3; ++d) {
            for (std::size_t c = 0; c < 6; ++c) {
                dt[d][c] = (tr.jac[0][c] * n[d] - tr.jac[1][c] * t1[d] - tr.jac[2][c] * t2[d]) * wj;
            }
        }
        // d f_a / d u_b: the point's displacement is sum N_b u_b on either side.
        for (std::size_t a = 0; a < 8; ++a) {
            for (std::size_t b = 0; b < 8; ++b) {
                const std::size_t side = b < 4 ? 0 : 3;
                for (std::size_t d = 0; d < 3; ++d) {
                    for (std::size_t e = 0; e < 3; ++e) {
                        const double v = N[a] * dt[d][side + e] * Nabs[b];
                        if (v != 0.0) {
                            K->push_back({3 * node[a] + static_cast<int>(d),
                                          3 * node[b] + static_cast<int>(e), v});
                        }
                    }
                }
            }
        }
    }
}

std::vector<std::array<int, 2>> MortarContact3D::couplings() const {
    std::vector<std::array<int, 2>> c;
    for (const auto& p : points_) {
        if (!p.master.in_contact) {
            continue;
        }
        std::array<int, 8> node{};
        for (std::size_t a = 0; a < 4; ++a) {
            node[a] = p.slave.nodes[a];
            node[a + 4] = p.master.nodes[a];
        }
        for (int a : node) {
            for (int b : node) {
                for (int d = 0; d < 3; ++d) {
                    for (int e = 0; e < 3; ++e) {
                        c.push_back({3 * a + d, 3 * b + e});
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

namespace ifsim::fem {

std::unique_ptr<MortarKinematics> make_mortar_3d(const Mesh& mesh, const std::string& slave_faces,
                                                 const std::string& master_faces) {
    return std::make_unique<MortarContact3D>(mesh, slave_faces, master_faces);
}

} // namespace ifsim::fem
