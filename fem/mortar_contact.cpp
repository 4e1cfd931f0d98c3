#include "fem/mortar_contact.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "fem/stress_extrapolation.hpp"

namespace ifsim::fem {
namespace {

// What differs between the dimensions' surfaces: the name of the segment a projection lands
// on, the frame's components and where a slave point sits in its element.
int segment(const SurfaceProjection& m) {
    return m.edge;
}
int segment(const SurfaceProjection3D& m) {
    return m.face;
}

void set_frame(const SurfaceProjection& m, ContactKinematics& k) {
    k.n = {m.normal[0], m.normal[1], 0.0};
    k.t1 = {m.tangent[0], m.tangent[1], 0.0};
    k.t2 = {0.0, 0.0, 1.0};
}
void set_frame(const SurfaceProjection3D& m, ContactKinematics& k) {
    k.n = m.normal;
    k.t1 = m.t1;
    k.t2 = m.t2;
}

void set_slave_location(const MortarSurface2D& surface, const SlavePoint& s, ContactKinematics& k) {
    const FaceRef& face = surface.edge_face(s.edge);
    k.slave_element = face.element;
    const auto xi = quad4_face_point(face.local_face, s.xi);
    k.slave_natural = {xi[0], xi[1], 0.0};
    k.x = {s.x[0], s.x[1], 0.0};
}
void set_slave_location(const MortarSurface3D& surface, const SlavePoint3D& s,
                        ContactKinematics& k) {
    k.slave_element = surface.face_ref(s.face).element;
    k.slave_natural = s.natural;
    k.x = s.x;
}

// 2D: f_a = N_a (t_N n - tau t) w j; d f_a / d u_b = N_a (dt_N n - dtau t) |N_b| w j.
void add_point_2d(const ContactTraction& tr, const std::array<double, 3>& n,
                  const std::array<double, 3>& t, double wj, const std::array<int, 4>& node,
                  const std::array<double, 4>& N, std::vector<double>& f_int,
                  std::vector<ContactTriplet>* K) {
    for (std::size_t a = 0; a < 4; ++a) {
        for (std::size_t d = 0; d < 2; ++d) {
            f_int[static_cast<std::size_t>(2 * node[a]) + d] +=
                N[a] * (tr.t_N * n[d] - tr.tau[0] * t[d]) * wj;
        }
    }
    if (K == nullptr) {
        return;
    }
    // The point's displacement is sum N_b u_b on either side: the Jacobian column of side s
    // (0 slave, 1 master) is weighted by |N_b|.
    for (std::size_t a = 0; a < 4; ++a) {
        for (std::size_t b = 0; b < 4; ++b) {
            const std::size_t side = b < 2 ? 0 : 1;
            const double Nb = std::abs(N[b]);
            for (std::size_t d = 0; d < 2; ++d) {
                for (std::size_t e = 0; e < 2; ++e) {
                    const double dtN = tr.jac[0][2 * side + e];
                    const double dtau = tr.jac[1][2 * side + e];
                    const double v = N[a] * (dtN * n[d] - dtau * t[d]) * Nb * wj;
                    if (v != 0.0) {
                        K->push_back({2 * node[a] + static_cast<int>(d),
                                      2 * node[b] + static_cast<int>(e), v});
                    }
                }
            }
        }
    }
}

// 3D: f_a = N_a (t_N n - tau1 t1 - tau2 t2) w j, with the traction vector and its columns
// formed once per point.
void add_point_3d(const ContactTraction& tr, const Vec3& n, const Vec3& t1, const Vec3& t2,
                  double wj, const std::array<int, 8>& node, const std::array<double, 8>& N,
                  const std::array<double, 8>& Nabs, std::vector<double>& f_int,
                  std::vector<ContactTriplet>* K) {
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
        return;
    }
    // d t / d u_side,e for both sides (columns [0,3) slave, [3,6) master of tr.jac).
    std::array<std::array<double, 6>, 3> dt{};
    for (std::size_t d = 0; d < 3; ++d) {
        for (std::size_t c = 0; c < 6; ++c) {
            dt[d][c] = (tr.jac[0][c] * n[d] - tr.jac[1][c] * t1[d] - tr.jac[2][c] * t2[d]) * wj;
        }
    }
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

} // namespace

template <int D>
MortarContact<D>::MortarContact(const Mesh& mesh, const std::string& slave_faces,
                                const std::string& master_faces)
    : slave_(mesh, slave_faces), master_(mesh, master_faces) {}

template <int D>
bool MortarContact<D>::pair(const Mesh& mesh, const std::vector<double>& u) {
    slave_.set_configuration(mesh, &u);
    master_.set_configuration(mesh, &u);
    const auto gauss = slave_.integration_points();
    const bool same_points = gauss.size() == points_.size();
    bool changed = !same_points;
    std::vector<Point> next(gauss.size());
    for (std::size_t i = 0; i < gauss.size(); ++i) {
        const auto& s = gauss[i];
        // Start from the previous master segment (-1 when inactive: the nearest); the
        // projection walks from there.
        const int start = same_points ? points_[i].master_segment : -1;
        const auto m = master_.project(s.x, start);
        Point& p = next[i];
        p.k.active = m.in_contact;
        p.master_segment = segment(m);
        if (m.in_contact) {
            p.g_N0 = normal_gap(m, s.x);
        }
        p.k.g_N = p.g_N0;
        set_frame(m, p.k);
        set_slave_location(slave_, s, p.k);
        p.k.weight = s.weight_j;
        for (std::size_t a = 0; a < face_nodes; ++a) {
            p.slave_nodes[a] = s.nodes[a];
            p.slave_N[a] = s.N[a];
            p.master_nodes[a] = m.nodes[a];
            p.master_N[a] = m.N[a];
        }
        counters_.projection_iterations += m.iterations;
        if (!changed) {
            changed = m.in_contact != points_[i].k.active ||
                      p.master_segment != points_[i].master_segment;
        }
    }
    points_ = std::move(next);
    ++counters_.pairings;
    counters_.projections += static_cast<long>(points_.size());
    counters_.pattern_changes += changed ? 1 : 0;
    return changed;
}

template <int D>
void MortarContact<D>::update_gaps(const std::vector<double>& du) {
    for (Point& p : points_) {
        if (!p.k.active) {
            continue;
        }
        std::array<double, D> dus{};
        std::array<double, D> dum{};
        for (std::size_t d = 0; d < D; ++d) {
            for (std::size_t a = 0; a < face_nodes; ++a) {
                dus[d] += p.slave_N[a] * du[static_cast<std::size_t>(D * p.slave_nodes[a]) + d];
                dum[d] += p.master_N[a] * du[static_cast<std::size_t>(D * p.master_nodes[a]) + d];
            }
        }
        // The gaps of Eqs. A11 and A13, summed per dimension in the order they have always
        // been (the compiler contracts these sums into fused multiply-adds: another order
        // moves the last digits of a history).
        if constexpr (D == 2) {
            p.k.g_N = p.g_N0 + (dus[0] - dum[0]) * p.k.n[0] + (dus[1] - dum[1]) * p.k.n[1];
            double dg = 0.0;
            for (std::size_t d = 0; d < 2; ++d) {
                const auto at = [&](int a) {
                    return du[static_cast<std::size_t>(2 * p.master_nodes[a]) + d];
                };
                const double master = p.master_N[0] * at(0) + p.master_N[1] * at(1);
                dg += (master - dus[d]) * p.k.t1[d];
            }
            p.k.dg_T = {dg, 0.0};
        } else {
            double g_N = p.g_N0;
            std::array<double, 2> dg_T{0.0, 0.0};
            for (std::size_t d = 0; d < 3; ++d) {
                g_N += (dus[d] - dum[d]) * p.k.n[d];
                dg_T[0] += (dum[d] - dus[d]) * p.k.t1[d]; // Eq. A13
                dg_T[1] += (dum[d] - dus[d]) * p.k.t2[d];
            }
            p.k.g_N = g_N;
            p.k.dg_T = dg_T;
        }
    }
}

template <int D>
void MortarContact<D>::assemble(std::span<const ContactTraction> traction,
                                std::vector<double>& f_int, std::vector<ContactTriplet>* K) const {
    if (traction.size() != points_.size()) {
        throw std::invalid_argument("MortarContact::assemble: one traction per contact point");
    }
    constexpr int nn = 2 * face_nodes; // nodes of a point: its slave and its master segment
    for (std::size_t i = 0; i < points_.size(); ++i) {
        const Point& p = points_[i];
        if (!p.k.active) {
            continue;
        }
        const ContactTraction& tr = traction[i];
        const auto& n = p.k.n;
        const auto& t1 = p.k.t1;
        const auto& t2 = p.k.t2;
        const double wj = p.k.weight;
        // The slave nodes (sign +1) and the master nodes (sign -1), with the shape function of
        // each at the point (Eqs. A20, A21); |N| weighs a node in its side's point motion.
        std::array<int, nn> node{};
        std::array<double, nn> N{};
        std::array<double, nn> Nabs{};
        for (std::size_t a = 0; a < face_nodes; ++a) {
            node[a] = p.slave_nodes[a];
            node[a + face_nodes] = p.master_nodes[a];
            N[a] = p.slave_N[a];
            N[a + face_nodes] = -p.master_N[a];
            Nabs[a] = p.slave_N[a];
            Nabs[a + face_nodes] = p.master_N[a];
        }
        // The force and tangent sums are written per dimension in the order each has always
        // been summed in, so that a refactoring does not move the last digits of a history.
        if constexpr (D == 2) {
            add_point_2d(tr, n, t1, wj, node, N, f_int, K);
        } else {
            add_point_3d(tr, n, t1, t2, wj, node, N, Nabs, f_int, K);
        }
    }
}

template <int D>
std::vector<std::array<int, 2>> MortarContact<D>::couplings() const {
    std::vector<std::array<int, 2>> c;
    for (const Point& p : points_) {
        if (!p.k.active) {
            continue;
        }
        std::array<int, 2 * face_nodes> node{};
        for (std::size_t a = 0; a < face_nodes; ++a) {
            node[a] = p.slave_nodes[a];
            node[a + face_nodes] = p.master_nodes[a];
        }
        for (int a : node) {
            for (int b : node) {
                for (int d = 0; d < D; ++d) {
                    for (int e = 0; e < D; ++e) {
                        c.push_back({D * a + d, D * b + e});
                    }
                }
            }
        }
    }
    std::sort(c.begin(), c.end());
    c.erase(std::unique(c.begin(), c.end()), c.end());
    return c;
}

template class MortarContact<2>;
template class MortarContact<3>;

std::unique_ptr<MortarKinematics> make_mortar_contact(const Mesh& mesh,
                                                      const std::string& slave_faces,
                                                      const std::string& master_faces) {
    if (mesh.dim() == 2) {
        return std::make_unique<MortarContact<2>>(mesh, slave_faces, master_faces);
    }
    return std::make_unique<MortarContact<3>>(mesh, slave_faces, master_faces);
}

} // namespace ifsim::fem
