// Mortar contact forces (Eqs. A20, A21) and their tangent on non-matching 2D surfaces:
// equilibrium between the sides, uniform pressure totals, the tangent against finite
// differences (penalty and sliding Coulomb), pairing changes while a block slides over
// several master edges.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "fem/mortar_contact.hpp"

namespace {

using namespace ifsim::fem;

// Master: elements under y = 0 at xm (face set "master_top"); slave: elements above
// y = -pen at xs (face set "slave_bottom").
Mesh two_bodies(const std::vector<double>& xm, const std::vector<double>& xs, double pen) {
    Mesh m;
    m.type = ElementType::quad4;
    auto row = [&](const std::vector<double>& x, double y0, double y1, const char* set, int face) {
        const int base = m.n_nodes();
        const int n = static_cast<int>(x.size());
        for (double v : x) {
            m.coordinates.insert(m.coordinates.end(), {v, y0});
        }
        for (double v : x) {
            m.coordinates.insert(m.coordinates.end(), {v, y1});
        }
        for (int i = 0; i + 1 < n; ++i) {
            m.connectivity.insert(m.connectivity.end(),
                                  {base + i, base + i + 1, base + n + i + 1, base + n + i});
            m.face_sets[set].push_back({m.n_elements() - 1, face});
        }
    };
    row(xm, -1.0, 0.0, "master_top", 2);
    row(xs, -pen, 1.0, "slave_bottom", 0);
    m.validate();
    return m;
}

// Penalty normal law and Coulomb friction (tau conjugate to Eq. A13's dg_T).
struct Law {
    double k_N = 1e5;
    double k_T = 5e4;
    double mu = 0.4;
    std::vector<ContactTraction> operator()(const MortarContact<2>& c) const {
        std::vector<ContactTraction> out(c.n_points());
        for (std::size_t i = 0; i < out.size(); ++i) {
            const ContactKinematics& p = c.point(i);
            if (!p.active || p.g_N >= 0.0) {
                continue;
            }
            auto& t = out[i];
            const auto& n = p.n;
            const auto& tg = p.t1;
            t.t_N = k_N * p.g_N;
            const double trial = k_T * p.dg_T[0];
            for (std::size_t d = 0; d < 2; ++d) { // g_N: slave +n, master -n; dg_T: master +t
                t.jac[0][d] = k_N * n[d];
                t.jac[0][2 + d] = -k_N * n[d];
            }
            if (std::abs(trial) <= -mu * t.t_N) {
                t.tau[0] = trial;
                for (std::size_t d = 0; d < 2; ++d) {
                    t.jac[1][d] = -k_T * tg[d];
                    t.jac[1][2 + d] = k_T * tg[d];
                }
            } else {
                const double s = trial > 0.0 ? 1.0 : -1.0;
                t.tau[0] = -mu * t.t_N * s;
                for (std::size_t c4 = 0; c4 < 4; ++c4) {
                    t.jac[1][c4] = -mu * s * t.jac[0][c4];
                }
            }
        }
        return out;
    }
};

std::vector<double> forces(MortarContact<2>& c, const Law& law, const std::vector<double>& du,
                           std::vector<ContactTriplet>* K) {
    c.update_gaps(du);
    const auto tr = law(c);
    std::vector<double> f(du.size(), 0.0);
    c.assemble(tr, f, K);
    return f;
}

double sum_dir(const std::vector<double>& f, const std::vector<int>& nodes, int d) {
    double s = 0.0;
    for (int a : nodes) {
        s += f[static_cast<std::size_t>(2 * a + d)];
    }
    return s;
}

TEST(ContactAssembly, UniformPressureOnNonMatchingMeshes) {
    const double pen = 1e-3;
    const Mesh m = two_bodies({0, 0.7, 1.5, 2.2, 3.0}, {0.3, 0.9, 1.8, 2.6}, pen);
    MortarContact<2> c(m, "slave_bottom", "master_top");
    const std::vector<double> u(m.coordinates.size(), 0.0);
    EXPECT_TRUE(c.pair(m, u));
    EXPECT_FALSE(c.pair(m, u)); // same configuration, same pairing
    Law law;
    const auto f = forces(c, law, u, nullptr);
    const auto slave = m.nodes_of_faces("slave_bottom");
    const auto master = m.nodes_of_faces("master_top");
    const double p = law.k_N * pen; // contact pressure
    const double length = 2.6 - 0.3;
    // Slave: internal force -p L downwards (the contact pushes it up), master the opposite.
    EXPECT_NEAR(sum_dir(f, slave, 1), -p * length, 1e-9 * p);
    EXPECT_NEAR(sum_dir(f, master, 1), p * length, 1e-9 * p);
    EXPECT_NEAR(sum_dir(f, slave, 0), 0.0, 1e-12 * p);
    // Slave nodes carry the consistent nodal forces of the uniform pressure (exact: the slave
    // shape functions are integrated by the slave edges' own Gauss rule).
    const double xs[4] = {0.3, 0.9, 1.8, 2.6};
    for (int i = 0; i < 4; ++i) {
        const double left = i > 0 ? xs[i] - xs[i - 1] : 0.0;
        const double right = i < 3 ? xs[i + 1] - xs[i] : 0.0;
        const int node = 10 + i; // slave bottom nodes follow the 10 master nodes
        EXPECT_NEAR(f[static_cast<std::size_t>(2 * node + 1)], -p * 0.5 * (left + right), 1e-9 * p);
    }
    // Moment balance about the origin: the forces act at the same points on both sides.
    double moment = 0.0;
    for (int a = 0; a < m.n_nodes(); ++a) {
        moment += m.coordinate(a, 0) * f[static_cast<std::size_t>(2 * a + 1)];
    }
    EXPECT_NEAR(moment, 0.0, 1e-9 * p);
}

void check_tangent(const Mesh& m, MortarContact<2>& c, const Law& law,
                   const std::vector<double>& du) {
    std::vector<ContactTriplet> K;
    const auto f0 = forces(c, law, du, &K);
    std::map<std::pair<int, int>, double> Kd;
    for (const auto& t : K) {
        Kd[{t.row, t.col}] += t.value;
    }
    const auto couplings = c.couplings();
    for (const auto& [rc, v] : Kd) { // every entry lies in the coupling pattern
        EXPECT_TRUE(std::binary_search(couplings.begin(), couplings.end(),
                                       std::array<int, 2>{rc.first, rc.second}));
    }
    const double h = 1e-9;
    double max_err = 0.0;
    double max_k = 0.0;
    for (int j = 0; j < 2 * m.n_nodes(); ++j) {
        auto dp = du;
        dp[static_cast<std::size_t>(j)] += h;
        auto dm = du;
        dm[static_cast<std::size_t>(j)] -= h;
        const auto fp = forces(c, law, dp, nullptr);
        const auto fm = forces(c, law, dm, nullptr);
        for (int i = 0; i < 2 * m.n_nodes(); ++i) {
            const double fd =
                (fp[static_cast<std::size_t>(i)] - fm[static_cast<std::size_t>(i)]) / (2 * h);
            const auto it = Kd.find({i, j});
            const double k = it == Kd.end() ? 0.0 : it->second;
            max_err = std::max(max_err, std::abs(fd - k));
            max_k = std::max(max_k, std::abs(k));
        }
    }
    (void)f0;
    EXPECT_GT(max_k, 0.0);
    EXPECT_LT(max_err, 1e-6 * max_k);
}

TEST(ContactAssembly, TangentMatchesFiniteDifferencesStickAndSlip) {
    const Mesh m = two_bodies({0, 0.7, 1.5, 2.2, 3.0}, {0.3, 0.9, 1.8, 2.6}, 1e-3);
    MortarContact<2> c(m, "slave_bottom", "master_top");
    std::vector<double> u(m.coordinates.size(), 0.0);
    c.pair(m, u);
    Law law;
    // Stick: a small relative tangential increment, nodal perturbations of both sides.
    std::vector<double> du(m.coordinates.size(), 0.0);
    for (int a = 0; a < m.n_nodes(); ++a) {
        du[static_cast<std::size_t>(2 * a)] = (a >= 10 ? 1e-6 : 0.0) + 1e-7 * std::sin(a);
        du[static_cast<std::size_t>(2 * a + 1)] = 1e-7 * std::cos(3.0 * a);
    }
    check_tangent(m, c, law, du);
    // Slip: a large relative tangential increment (|k_T dg_T| > mu |t_N|).
    for (int a = 10; a < m.n_nodes(); ++a) {
        du[static_cast<std::size_t>(2 * a)] += 1e-2;
    }
    c.update_gaps(du);
    const auto tr = law(c);
    for (std::size_t i = 0; i < tr.size(); ++i) {
        if (c.point(i).active) {
            EXPECT_NEAR(std::abs(tr[i].tau[0]), -law.mu * tr[i].t_N, 1e-12 * std::abs(tr[i].t_N));
        }
    }
    check_tangent(m, c, law, du);
}

TEST(ContactAssembly, BlockSlidesOverSeveralMasterEdges) {
    // A slave block of one edge (0.8 wide) slides right over a plate of 6 edges of 0.5 in
    // increments of 0.3: the pairing changes, the transmitted tangential force is mu times
    // the normal force on both sides while sliding, and the block leaves the plate at the end.
    const double pen = 1e-3;
    const Mesh m = two_bodies({0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0}, {0.1, 0.9}, pen);
    MortarContact<2> c(m, "slave_bottom", "master_top");
    std::vector<double> u(m.coordinates.size(), 0.0);
    Law law;
    const auto slave = m.nodes_of_faces("slave_bottom");
    const auto master = m.nodes_of_faces("master_top");
    std::vector<int> edges_seen;
    int changes = 0;
    int full_steps = 0;
    for (int step = 0; step < 10; ++step) {
        changes += c.pair(m, u) ? 1 : 0;
        std::vector<double> du(u.size(), 0.0);
        for (int a : m.nodes_of_faces("slave_bottom")) {
            du[static_cast<std::size_t>(2 * a)] = 0.3;
        }
        // Upper slave nodes move too (the whole block slides).
        du[static_cast<std::size_t>(2 * (m.n_nodes() - 1))] = 0.3;
        du[static_cast<std::size_t>(2 * (m.n_nodes() - 2))] = 0.3;
        const auto f = forces(c, law, du, nullptr);
        int active = 0;
        for (std::size_t i = 0; i < c.n_points(); ++i) {
            if (c.point(i).active) {
                ++active;
                edges_seen.push_back(c.master_segment(i));
            }
        }
        if (active == 2) { // fully on the plate
            ++full_steps;
            const double N_s = sum_dir(f, slave, 1);
            const double T_s = sum_dir(f, slave, 0);
            EXPECT_NEAR(N_s, -law.k_N * pen * 0.8, 1e-9);
            EXPECT_NEAR(std::abs(T_s), law.mu * std::abs(N_s), 1e-9);
            EXPECT_NEAR(sum_dir(f, master, 0), -T_s, 1e-9);
            // Friction on the slave resists its motion to the right: internal force +x.
            EXPECT_GT(T_s, 0.0);
        }
        for (std::size_t i = 0; i < u.size(); ++i) {
            u[i] += du[i];
        }
    }
    std::sort(edges_seen.begin(), edges_seen.end());
    edges_seen.erase(std::unique(edges_seen.begin(), edges_seen.end()), edges_seen.end());
    EXPECT_EQ(edges_seen.size(), 6U); // every master edge carried the block
    EXPECT_GE(changes, 5);
    EXPECT_GE(full_steps, 5);
    // Finally beyond the plate's natural border: no point in contact.
    c.pair(m, u);
    for (std::size_t i = 0; i < c.n_points(); ++i) {
        EXPECT_FALSE(c.point(i).active);
    }
}

} // namespace
