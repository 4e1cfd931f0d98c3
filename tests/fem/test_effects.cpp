// Only the effects a scene asks for: a block without gravity, K0 stress or pressure spends
// nothing on them (counters and timers stay exactly zero); with them, the work is counted,
// and a K0 stress with matching gravity is in equilibrium from the start. The counters of
// the Newton iteration and the constitutive work add up.
#include <gtest/gtest.h>

#include "tests/fem/fem_test_support.hpp"

using namespace ifsim;
using namespace ifsim::fem;
using namespace ifsim::fem::testing;

namespace {

Stage oedometer(int steps, double change) {
    Stage st;
    st.steps = steps;
    st.displacements = {{"left", 0, 0.0},   {"right", 0, 0.0},  {"front", 1, 0.0},
                        {"back", 1, 0.0},   {"bottom", 0, 0.0}, {"bottom", 1, 0.0},
                        {"bottom", 2, 0.0}, {"top", 2, change}};
    return st;
}

} // namespace

TEST(Effects, NoGravityNoK0NoPressureCostsNothing) {
    Mesh m = box_mesh({1.0, 1.0, 2.0, 2, 2, 4});
    StaticSolver solver(m, {material(karlsruhe(), hypo_state({-80, -80, -80, 0, 0, 0}, 0.7))}, {});
    ASSERT_TRUE(solver.run_stage(oedometer(3, -2e-3)).ok);
    const auto& c = solver.counters();
    const auto& t = solver.timers();
    EXPECT_GT(c.newton_iterations + c.predictor_solves, 0);
    EXPECT_EQ(c.gravity_load_builds, 0);
    EXPECT_EQ(c.gravity_load_applications, 0);
    EXPECT_EQ(c.pressure_load_builds, 0);
    EXPECT_EQ(c.k0_points, 0);
    EXPECT_EQ(t.gravity, 0.0);
    EXPECT_EQ(t.k0, 0.0);
    EXPECT_EQ(t.pressure, 0.0);
    EXPECT_GT(t.element, 0.0);
    EXPECT_GT(t.assembly, 0.0);
    EXPECT_GT(t.solve, 0.0);
}

TEST(Effects, K0StressWithMatchingGravityIsInEquilibrium) {
    const double rho = 1.6, g = 9.81;
    Mesh m = box_mesh({1.0, 1.0, 2.0, 2, 2, 4});
    auto mat = material(karlsruhe(), hypo_state({-80, -80, -80, 0, 0, 0}, 0.7));
    mat.density = rho;
    mat.k0 = K0Stress{2.0, rho * g, 10.0, 0.45};
    StaticSolver solver(m, {mat}, {});
    EXPECT_EQ(solver.counters().k0_points, m.n_elements() * 8);
    EXPECT_GT(solver.timers().k0, 0.0);
    // The initial stress is sigma_v = -(10 + gamma (2 - z)), sigma_h = 0.45 sigma_v.
    const auto& geo = solver.geometry();
    for (int e = 0; e < m.n_elements(); ++e) {
        for (int q = 0; q < 8; ++q) {
            const double z = geo.ip_coordinates[static_cast<std::size_t>((e * 8 + q) * 3 + 2)];
            const auto y = solver.state(e, q);
            EXPECT_NEAR(y[2], -(10.0 + rho * g * (2.0 - z)), 1e-12);
            EXPECT_NEAR(y[0], 0.45 * y[2], 1e-12);
            EXPECT_EQ(y[6], 0.7); // the rest of the initial state is kept
        }
    }
    Stage st = oedometer(2, 0.0);
    st.gravity = GravityRamp{g, g};
    st.pressures = {{"top", 10.0, 10.0}};
    std::vector<IncrementInfo> infos;
    ASSERT_TRUE(solver.run_stage(st, [&](const IncrementInfo& i) { infos.push_back(i); }).ok);
    EXPECT_EQ(solver.counters().newton_iterations, 0); // converged at the first evaluation
    ASSERT_EQ(infos.size(), 2u);
    EXPECT_LT(infos[0].residuals[0], 1e-12);
    EXPECT_LT(max_abs(solver.displacement()), 1e-15);
    EXPECT_EQ(solver.counters().gravity_load_builds, 1);
    // The initial-imbalance check of the first stage, two increments, and the first one's
    // tangent predictor (passes at zero increment and at the zero guess; its own guess is the
    // increment's evaluation unless rejected, then evaluated again).
    const auto& k = solver.counters();
    EXPECT_EQ(k.predictor_solves, 1);
    EXPECT_EQ(k.gravity_load_applications, 1 + 2 + 2 * k.predictor_solves + k.predictor_rejections);
    EXPECT_EQ(solver.counters().pressure_load_builds, 1);
    EXPECT_GT(solver.timers().gravity, 0.0);
}

TEST(Effects, ConstitutiveWorkIsCountedPerLane) {
    Mesh m = box_mesh({1.0, 1.0, 1.0, 2, 2, 2});
    const auto points = static_cast<long>(m.n_elements() * 8);
    for (auto kind : {TangentKind::perturbation, TangentKind::rate}) {
        SolverSettings s;
        s.tangent.kind = kind;
        StaticSolver solver(m, {material(karlsruhe(), hypo_state({-80, -80, -80, 0, 0, 0}, 0.7))},
                            s);
        Stage st;
        st.steps = 2;
        st.displacements = {{"bottom", 0, 0.0}, {"bottom", 1, 0.0}, {"bottom", 2, 0.0},
                            {"left", 0, 0.0},   {"right", 0, 0.0},  {"front", 1, 0.0},
                            {"back", 1, 0.0}};
        st.equal_displacements = {{"top", 2}};
        st.pressures = {{"top", 80.0, 120.0}};
        ASSERT_TRUE(solver.run_stage(st).ok);
        const auto& c = solver.counters();
        // Residual evaluations: one per increment and Newton iteration, the first stage's check
        // of the initial equilibrium, and for the tangent predictor (the stage's first
        // increment) one at zero increment and one at each guess it compares; a kept tangent
        // guess is the increment's own evaluation, a rejected one is evaluated again.
        EXPECT_EQ(c.predictor_solves, 1);
        const long evaluations = c.increments + c.newton_iterations + 1 + 2 * c.predictor_solves +
                                 c.predictor_rejections;
        EXPECT_EQ(c.increments, 2);
        if (kind == TangentKind::perturbation) {
            // 6 adaptive perturbed lanes per point, Newton iteration and predictor (3D).
            EXPECT_EQ(c.tangent_evaluations,
                      6 * points * (c.newton_iterations + c.predictor_solves));
        } else {
            EXPECT_EQ(c.tangent_evaluations, 0);
        }
        EXPECT_EQ(c.constitutive_evaluations, points * evaluations + c.tangent_evaluations);
        EXPECT_EQ(c.tangent_fallbacks, 0);
    }
}
