// Continuum patch test (linear elasticity): on distorted quad4 and hex8 meshes a displacement
// field of constant strain (plus a small rotation) gives the exact constant stress at every
// integration point and zero residual at the interior nodes, with full and with reduced
// (uniform-gradient + hourglass) integration; solving with the boundary prescribed recovers
// the exact interior displacements.
#include <gtest/gtest.h>

#include <set>

#include "tests/fem/fem_test_support.hpp"

using namespace ifsim;
using namespace ifsim::fem;
using namespace ifsim::fem::testing;

namespace {

constexpr double E = 1.0e4;
constexpr double nu = 0.3;

// u_i = (eps_ij + omega_ij) x_j
struct Field {
    Sym<double> eps;
    double omega[3][3];
    std::vector<double> at(const Mesh& m) const {
        const int D = m.dim();
        std::vector<double> u(static_cast<std::size_t>(m.n_nodes() * D), 0.0);
        const double T[3][3] = {
            {eps[0], eps[3], eps[4]}, {eps[3], eps[1], eps[5]}, {eps[4], eps[5], eps[2]}};
        for (int n = 0; n < m.n_nodes(); ++n) {
            for (int i = 0; i < D; ++i) {
                double v = 0.0;
                for (int j = 0; j < D; ++j) {
                    v += (T[i][j] + omega[i][j]) * m.coordinate(n, j);
                }
                u[static_cast<std::size_t>(n * D + i)] = v;
            }
        }
        return u;
    }
};

Field field(int dim) {
    if (dim == 2) {
        return {{1.0e-3, -2.0e-3, 0.0, 0.5e-3, 0.0, 0.0},
                {{0.0, 0.3e-3, 0.0}, {-0.3e-3, 0.0, 0.0}, {0.0, 0.0, 0.0}}};
    }
    return {{1.0e-3, -2.0e-3, 0.5e-3, 0.4e-3, -0.3e-3, 0.2e-3},
            {{0.0, 0.3e-3, -0.1e-3}, {-0.3e-3, 0.0, 0.2e-3}, {0.1e-3, -0.2e-3, 0.0}}};
}

Mesh distorted_mesh(int dim) {
    Mesh m = dim == 2 ? rectangle_mesh({2.0, 1.5, 4, 3}) : box_mesh({1.0, 1.2, 0.9, 3, 2, 3});
    distort(m, 0.2, 0.3);
    return m;
}

std::set<int> boundary_nodes(const Mesh& m) {
    std::set<int> b;
    for (const char* s : {"left", "right", "bottom", "top", "front", "back"}) {
        if (m.node_sets.contains(s)) {
            b.insert(m.node_sets.at(s).begin(), m.node_sets.at(s).end());
        }
    }
    return b;
}

// One node set per boundary node with the exact field as its prescribed change.
Stage boundary_stage(Mesh& m, const std::vector<double>& u) {
    Stage st;
    const int D = m.dim();
    for (int n : boundary_nodes(m)) {
        const std::string set = single_node_set(m, n);
        for (int i = 0; i < D; ++i) {
            st.displacements.push_back({set, i, u[static_cast<std::size_t>(n * D + i)]});
        }
    }
    return st;
}

void expect_exact_stress(const StaticSolver& s, const Sym<double>& expected, bool trial) {
    const double scale = 10.0; // kPa: |sigma| of the field is ~ 20-60 kPa
    for (int e = 0; e < s.mesh().n_elements(); ++e) {
        for (int q = 0; q < s.points_per_element(); ++q) {
            const auto y = trial ? s.trial_state(e, q) : s.state(e, q);
            for (int k = 0; k < 6; ++k) {
                ASSERT_NEAR(y[static_cast<std::size_t>(k)], expected[static_cast<std::size_t>(k)],
                            1e-10 * scale)
                    << "element " << e << " point " << q << " component " << k;
            }
        }
    }
}

void probe_patch(int dim, Integration integration) {
    Mesh m = distorted_mesh(dim);
    const Field f = field(dim);
    const auto u = f.at(m);
    const Stage st = boundary_stage(m, u);
    SolverSettings settings;
    settings.integration = integration;
    StaticSolver solver(m, {material(LinearElasticParams{E, nu}, elastic_state())}, settings);
    solver.begin_stage(st);
    ASSERT_GT(solver.dof_map().n_equations, 0); // interior nodes are free
    std::string error;
    ASSERT_TRUE(solver.evaluate(1.0, u, false, error)) << error;
    // Residual at the interior (free) equations vanishes; forces are ~ sigma * area ~ 10 kN.
    EXPECT_LT(max_abs(solver.residual()), 1e-11) << "interior residual";
    Sym<double> eps = f.eps;
    if (dim == 2) {
        eps[2] = eps[4] = eps[5] = 0.0; // plane strain
    }
    expect_exact_stress(solver, hooke(E, nu, eps), true);

    // Control: a quadratic field is not in equilibrium, so the same check would catch it.
    auto uq = u;
    for (int n = 0; n < m.n_nodes(); ++n) {
        uq[static_cast<std::size_t>(n * dim)] += 1e-3 * m.coordinate(n, 1) * m.coordinate(n, 1);
    }
    ASSERT_TRUE(solver.evaluate(1.0, uq, false, error)) << error;
    EXPECT_GT(max_abs(solver.residual()), 1e-3);
}

} // namespace

TEST(PatchTest, Quad4FullIntegrationInteriorResidualVanishes) {
    probe_patch(2, Integration::full);
}
TEST(PatchTest, Quad4ReducedIntegrationInteriorResidualVanishes) {
    probe_patch(2, Integration::reduced);
}
TEST(PatchTest, Hex8FullIntegrationInteriorResidualVanishes) {
    probe_patch(3, Integration::full);
}
TEST(PatchTest, Hex8ReducedIntegrationInteriorResidualVanishes) {
    probe_patch(3, Integration::reduced);
}

TEST(PatchTest, SolvedInteriorDisplacementsAndStressesAreExact) {
    for (int dim : {2, 3}) {
        for (Integration integ : {Integration::full, Integration::reduced}) {
            Mesh m = distorted_mesh(dim);
            const Field f = field(dim);
            const auto u = f.at(m);
            const Stage st = boundary_stage(m, u);
            SolverSettings settings;
            settings.integration = integ;
            StaticSolver solver(m, {material(LinearElasticParams{E, nu}, elastic_state())},
                                settings);
            const auto res = solver.run_stage(st);
            ASSERT_TRUE(res.ok) << res.reason;
            for (std::size_t d = 0; d < u.size(); ++d) {
                ASSERT_NEAR(solver.displacement()[d], u[d], 1e-14) << "dof " << d;
            }
            Sym<double> eps = f.eps;
            if (dim == 2) {
                eps[2] = eps[4] = eps[5] = 0.0; // plane strain
            }
            expect_exact_stress(solver, hooke(E, nu, eps), false);
            // The reactions balance: the internal forces sum to zero in each direction.
            for (int i = 0; i < dim; ++i) {
                double sum = 0.0;
                for (int n = 0; n < m.n_nodes(); ++n) {
                    sum += solver.internal_force()[static_cast<std::size_t>(n * dim + i)];
                }
                EXPECT_NEAR(sum, 0.0, 1e-10);
            }
        }
    }
}
