// Updated Lagrangian with the Zaremba-Jaumann rate ([mesh] kinematics = "updated-lagrangian";
// fem/finite_strain.hpp): a prestressed element turned rigidly by 90 degrees in steps turns
// its stress (and intergranular strain) with it and keeps their invariants; large simple shear
// of linear elasticity follows the Jaumann closed form sigma_12 = G sin(gamma), sigma_11 =
// -sigma_22 = G (1 - cos(gamma)) at second order in the step; the small-deformation limit is
// the small-strain solver's answer; Newton stays quadratic.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "fem/continuum_assembly.hpp"
#include "fem/finite_strain.hpp"
#include "tests/fem/fem_test_support.hpp"

using namespace ifsim;
using namespace ifsim::fem;
using namespace ifsim::fem::testing;

namespace {

SolverSettings updated_lagrangian() {
    SolverSettings s;
    s.kinematics = Kinematics::updated_lagrangian;
    return s;
}

// Drives the continuum of a mesh through prescribed total displacement fields u_k = field(k)
// (every node prescribed: a homogeneous motion), increment by increment.
template <class Field>
void drive(const Mesh& m, ContinuumAssembly& c, int steps, Field field) {
    std::vector<double> u(static_cast<std::size_t>(m.n_nodes() * m.dim()), 0.0);
    for (int k = 1; k <= steps; ++k) {
        const std::vector<double> next = field(k);
        std::vector<double> du(u.size());
        for (std::size_t d = 0; d < u.size(); ++d) {
            du[d] = next[d] - u[d];
        }
        c.begin_increment(m, u);
        c.strains(m, du);
        std::string error;
        ASSERT_TRUE(c.update(error)) << error;
        c.commit();
        u = next;
    }
}

// Total displacement (Q - I) X of every node.
std::vector<double> rigid(const Mesh& m, const Mat3& Q) {
    const int D = m.dim();
    std::vector<double> u(static_cast<std::size_t>(m.n_nodes() * D));
    for (int n = 0; n < m.n_nodes(); ++n) {
        Eigen::Vector3d X = Eigen::Vector3d::Zero();
        for (int i = 0; i < D; ++i) {
            X(i) = m.coordinate(n, i);
        }
        const Eigen::Vector3d x = Q * X;
        for (int i = 0; i < D; ++i) {
            u[static_cast<std::size_t>(n * D + i)] = x(i) - X(i);
        }
    }
    return u;
}

Mat3 turn(double angle, const Eigen::Vector3d& axis) {
    return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

} // namespace

TEST(UpdatedLagrangian, RigidRotationTurnsTheStateAndKeepsItsInvariants) {
    for (const int D : {2, 3}) {
        SCOPED_TRACE(D);
        const Mesh m =
            D == 2 ? rectangle_mesh({1.0, 0.5, 1, 1}) : box_mesh({1.0, 0.5, 0.8, 1, 1, 1});
        const Sym<double> s0 = D == 2 ? Sym<double>{-100.0, -60.0, -30.0, 12.0, 0.0, 0.0}
                                      : Sym<double>{-100.0, -60.0, -30.0, 12.0, 5.0, -8.0};
        std::vector<double> y0 = hypo_state(s0, 0.7);
        // |h0| < R = 5e-5 (Table 3), so the model keeps its size
        const Sym<double> h0 = D == 2 ? Sym<double>{2e-5, -1e-5, 0.0, 1.5e-5, 0.0, 0.0}
                                      : Sym<double>{2e-5, -1e-5, 0.5e-5, 1.5e-5, -0.5e-5, 1e-5};
        for (int j = 0; j < 6; ++j) {
            y0[static_cast<std::size_t>(Hypoplasticity::h_index + j)] =
                h0[static_cast<std::size_t>(j)];
        }
        double k0_seconds = 0.0;
        ContinuumAssembly c(m, {material(karlsruhe(), y0)}, updated_lagrangian(), k0_seconds);
        const Eigen::Vector3d axis = D == 2 ? Eigen::Vector3d(0, 0, 1) : Eigen::Vector3d(1, 2, 3);
        const double quarter = std::numbers::pi / 2.0;
        const int steps = 30;
        drive(m, c, steps, [&](int k) { return rigid(m, turn(quarter * k / steps, axis)); });
        const Mat3 Q = turn(quarter, axis);
        const Sym<double> expected = rotate(Q, s0);
        const Sym<double> expected_h = rotate(Q, h0);
        for (int q = 0; q < (D == 2 ? 4 : 8); ++q) {
            const std::vector<double> y = c.state(0, q);
            for (int j = 0; j < 6; ++j) {
                EXPECT_NEAR(y[static_cast<std::size_t>(j)], expected[static_cast<std::size_t>(j)],
                            1e-9)
                    << "sigma " << j;
                EXPECT_NEAR(y[static_cast<std::size_t>(Hypoplasticity::h_index + j)],
                            expected_h[static_cast<std::size_t>(j)], 1e-15)
                    << "h " << j;
            }
            const Mat3 S = as_matrix({y[0], y[1], y[2], y[3], y[4], y[5]});
            const Mat3 S0 = as_matrix(s0);
            EXPECT_NEAR(S.trace(), S0.trace(), 1e-9);
            EXPECT_NEAR(S.determinant(), S0.determinant(), 1e-6 * std::abs(S0.determinant()));
            EXPECT_NEAR((S * S).trace(), (S0 * S0).trace(), 1e-7);
            EXPECT_NEAR(y[6], 0.7, 1e-14); // no volume change, no void ratio change
        }
    }
}

// Jaumann rate, hypoelastic: sigma_12 = G sin(gamma), sigma_11 = -sigma_22 = G (1 - cos gamma)
// (Dienes 1979), the displacement u_x = gamma y imposed on every node.
TEST(UpdatedLagrangian, LargeSimpleShearFollowsTheJaumannClosedForm) {
    const double E = 1.0e4, nu = 0.25, G = E / (2.0 * (1.0 + nu));
    const double gamma = 1.0;
    double error[2] = {0.0, 0.0};
    for (const int D : {2, 3}) {
        for (int r = 0; r < 2; ++r) {
            const int steps = r == 0 ? 50 : 200;
            const Mesh m =
                D == 2 ? rectangle_mesh({1.0, 1.0, 1, 1}) : box_mesh({1.0, 1.0, 1.0, 1, 1, 1});
            double k0_seconds = 0.0;
            ContinuumAssembly c(m, {material(LinearElasticParams{E, nu}, elastic_state())},
                                updated_lagrangian(), k0_seconds);
            const int v = D - 1; // shear along x on planes of constant vertical coordinate
            drive(m, c, steps, [&](int k) {
                std::vector<double> u(static_cast<std::size_t>(m.n_nodes() * D), 0.0);
                for (int n = 0; n < m.n_nodes(); ++n) {
                    u[static_cast<std::size_t>(n * D)] = gamma * k / steps * m.coordinate(n, v);
                }
                return u;
            });
            const std::vector<double> y = c.state(0, 0);
            const double s12 = D == 2 ? y[3] : y[4]; // x-y (2D) or x-z (3D)
            const double s11 = y[0], s22 = y[static_cast<std::size_t>(v)];
            const double e = std::max({std::abs(s12 - G * std::sin(gamma)),
                                       std::abs(s11 - G * (1.0 - std::cos(gamma))),
                                       std::abs(s22 + G * (1.0 - std::cos(gamma)))});
            std::printf("%dD simple shear to gamma = 1 in %d steps: largest error %.3e kPa "
                        "(G = %.0f kPa)\n",
                        D, steps, e, G);
            error[r] = e;
            EXPECT_LT(e, 2e-3 * G);
        }
        // Second order in the step: four times the steps, about a sixteenth of the error.
        EXPECT_LT(error[1], error[0] / 10.0);
    }
}

namespace {

// A block between a fixed base and a top plate that moves by (a, 0, -a/2), its initial
// lateral stress held by pressures (on the reference faces in both kinematics): displacements
// and integration-point stresses after the stage, minus the initial ones.
std::vector<double> block_response(Kinematics k, double a, const ElementSetMaterial& mat) {
    Mesh m = box_mesh({1.0, 0.5, 1.0, 2, 1, 2});
    distort(m, 0.1, 0.5);
    SolverSettings s;
    s.kinematics = k;
    s.residual_tolerance = 1e-11;
    s.max_cuts = 0;
    StaticSolver solver(m, {mat}, s);
    Stage st;
    st.steps = 4;
    st.displacements = {{"bottom", 0, 0.0}, {"bottom", 1, 0.0}, {"bottom", 2, 0.0},
                        {"top", 0, a},      {"top", 1, 0.0},    {"top", 2, -0.5 * a},
                        {"front", 1, 0.0},  {"back", 1, 0.0}};
    const double lateral = -mat.initial_state[0];
    st.pressures = {{"left", lateral, lateral}, {"right", lateral, lateral}};
    const auto r = solver.run_stage(st);
    EXPECT_TRUE(r.ok) << r.reason;
    std::vector<double> out = solver.displacement();
    for (int e = 0; e < m.n_elements(); ++e) {
        for (int q = 0; q < 8; ++q) {
            const auto y = solver.state(e, q);
            for (std::size_t j = 0; j < 6; ++j) {
                out.push_back(y[j] - mat.initial_state[j]);
            }
        }
    }
    return out;
}

// max |a - b| / max |b|: the difference relative to the response.
double relative_difference(const std::vector<double>& a, const std::vector<double>& b) {
    double num = 0.0, den = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        num = std::max(num, std::abs(a[i] - b[i]));
        den = std::max(den, std::abs(b[i]));
    }
    return num / den;
}

double limit_difference(const ElementSetMaterial& mat, double a) {
    const double d = relative_difference(block_response(Kinematics::updated_lagrangian, a, mat),
                                         block_response(Kinematics::small_strain, a, mat));
    std::printf("top displacement %.0e m: UL vs small strain, largest difference relative to "
                "the response %.3e\n",
                a, d);
    return d;
}

} // namespace

// The small-deformation limit. Without initial stress the difference to the small-strain
// solver vanishes in proportion to the displacement (the geometric terms are O(strain)).
// With an initial stress sigma_0 the updated Lagrangian keeps its initial-stress stiffness
// (O(sigma_0 / stiffness) of the response, measured 3e-4 to 5e-4 for 100 kPa on hypoplastic
// sand), which small strain leaves out at any amplitude.
TEST(UpdatedLagrangian, SmallDeformationLimitIsTheSmallStrainSolution) {
    const ElementSetMaterial elastic =
        material(LinearElasticParams{1.0e5, 0.3}, {0, 0, 0, 0, 0, 0, 0.65});
    const double d4 = limit_difference(elastic, 1e-4);
    const double d5 = limit_difference(elastic, 1e-5);
    EXPECT_LT(d4, 1e-3);
    EXPECT_GT(d4 / d5, 8.0); // first order in the displacement
    EXPECT_LT(d4 / d5, 12.0);
    const ElementSetMaterial sand =
        material(karlsruhe(), hypo_state({-50, -50, -100, 0, 0, 0}, 0.65));
    EXPECT_LT(limit_difference(sand, 1e-5), 2e-3);
    EXPECT_LT(limit_difference(sand, 1e-6), 2e-3);
}

// Quadratic convergence with the consistent tangent: linear elasticity (the tangent is exact)
// through a large compression and shear of a distorted block in two increments.
TEST(UpdatedLagrangian, NewtonStaysQuadratic) {
    Mesh m = box_mesh({1.0, 1.0, 1.0, 2, 2, 2});
    distort(m, 0.1, 0.5);
    SolverSettings s = updated_lagrangian();
    s.residual_tolerance = 1e-13;
    s.max_cuts = 0;
    s.predictor = Predictor::zero;
    StaticSolver solver(m, {material(LinearElasticParams{1.0e4, 0.3}, elastic_state(10.0))}, s);
    Stage st;
    st.steps = 2;
    st.displacements = {{"bottom", 0, 0.0}, {"bottom", 1, 0.0}, {"bottom", 2, 0.0},
                        {"top", 0, 0.2},    {"top", 1, 0.0},    {"top", 2, -0.15}};
    std::vector<IncrementInfo> infos;
    const auto r = solver.run_stage(st, [&](const IncrementInfo& i) { infos.push_back(i); });
    ASSERT_TRUE(r.ok) << r.reason;
    for (const IncrementInfo& info : infos) {
        std::printf("UL Newton, step %d:", info.step);
        for (double x : info.residuals) {
            std::printf(" %.2e", x);
        }
        std::printf("\n");
        const auto& res = info.residuals;
        ASSERT_GE(res.size(), 3u);
        int quadratic = 0;
        for (std::size_t k = 1; k + 1 < res.size(); ++k) {
            if (res[k] < 1e-2 && res[k + 1] > 1e-14) {
                EXPECT_LT(res[k + 1], 10.0 * res[k] * res[k]) << "iteration " << k;
                ++quadratic;
            }
        }
        EXPECT_GE(quadratic, 1);
        EXPECT_LE(res.size(), 8u);
    }
}
