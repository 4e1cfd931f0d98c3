// Compression blocks of linear elasticity with closed-form answers: oedometric compression by a
// prescribed top displacement, uniaxial compression by a top pressure (3D and plane strain),
// and a laterally confined column under ramped gravity.
#include <gtest/gtest.h>

#include "tests/fem/fem_test_support.hpp"

using namespace ifsim;
using namespace ifsim::fem;
using namespace ifsim::fem::testing;

namespace {

constexpr double E = 2.0e4;
constexpr double nu = 0.3;
constexpr double G = E / (2.0 * (1.0 + nu));
constexpr double lambda = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));

// Reaction (internal minus external force) summed over a node set: the force the supports
// exert on the body, negated.
double reaction(const StaticSolver& s, const std::string& set, int dir) {
    const int D = s.mesh().dim();
    double sum = 0.0;
    for (int n : s.mesh().node_set(set)) {
        const auto d = static_cast<std::size_t>(n * D + dir);
        sum += s.internal_force()[d] - s.external_force()[d];
    }
    return sum;
}

} // namespace

TEST(CompressionBlock, OedometricByTopDisplacement) {
    for (Integration integ : {Integration::full, Integration::reduced}) {
        const double W = 1.0, Dp = 0.8, H = 2.0, delta = 4.0e-3;
        Mesh m = box_mesh({W, Dp, H, 3, 2, 4});
        SolverSettings settings;
        settings.integration = integ;
        StaticSolver solver(m, {material(LinearElasticParams{E, nu}, elastic_state())}, settings);
        Stage st;
        st.steps = 3;
        st.displacements = {{"left", 0, 0.0}, {"right", 0, 0.0},  {"front", 1, 0.0},
                            {"back", 1, 0.0}, {"bottom", 2, 0.0}, {"top", 2, -delta}};
        const auto res = solver.run_stage(st);
        ASSERT_TRUE(res.ok) << res.reason;
        EXPECT_EQ(res.increments, 3);
        const double eps = -delta / H;
        for (int e = 0; e < m.n_elements(); ++e) {
            for (int q = 0; q < solver.points_per_element(); ++q) {
                const auto y = solver.state(e, q);
                EXPECT_NEAR(y[2], (lambda + 2.0 * G) * eps, 1e-9);
                EXPECT_NEAR(y[0], lambda * eps, 1e-9);
                EXPECT_NEAR(y[1], lambda * eps, 1e-9);
                EXPECT_NEAR(y[3], 0.0, 1e-9);
            }
        }
        // The top nodes' internal force is sigma_zz times the area (compression: downwards).
        EXPECT_NEAR(reaction(solver, "top", 2), (lambda + 2.0 * G) * eps * W * Dp, 1e-8);
    }
}

TEST(CompressionBlock, UniaxialByTopPressure3D) {
    const double W = 1.0, Dp = 0.5, H = 1.5, p = 50.0;
    Mesh m = box_mesh({W, Dp, H, 2, 2, 3});
    StaticSolver solver(m, {material(LinearElasticParams{E, nu}, elastic_state())}, {});
    Stage st;
    st.steps = 2;
    st.displacements = {{"left", 0, 0.0}, {"front", 1, 0.0}, {"bottom", 2, 0.0}};
    st.pressures = {{"top", 0.0, p}};
    const auto res = solver.run_stage(st);
    ASSERT_TRUE(res.ok) << res.reason;
    const int D = 3;
    for (int n : m.node_set("top")) {
        EXPECT_NEAR(solver.displacement()[static_cast<std::size_t>(n * D + 2)], -p * H / E, 1e-12);
    }
    for (int n : m.node_set("right")) {
        EXPECT_NEAR(solver.displacement()[static_cast<std::size_t>(n * D + 0)], nu * p * W / E,
                    1e-12);
    }
    for (int e = 0; e < m.n_elements(); ++e) {
        const auto y = solver.state(e, 0);
        EXPECT_NEAR(y[2], -p, 1e-9);
        EXPECT_NEAR(y[0], 0.0, 1e-9);
        EXPECT_NEAR(y[1], 0.0, 1e-9);
    }
}

TEST(CompressionBlock, UniaxialByTopPressurePlaneStrain) {
    const double W = 2.0, H = 1.0, p = 80.0;
    Mesh m = rectangle_mesh({W, H, 4, 2});
    StaticSolver solver(m, {material(LinearElasticParams{E, nu}, elastic_state())}, {});
    Stage st;
    st.displacements = {{"left", 0, 0.0}, {"bottom", 1, 0.0}};
    st.pressures = {{"top", 0.0, p}};
    const auto res = solver.run_stage(st);
    ASSERT_TRUE(res.ok) << res.reason;
    const double eps_yy = -p * (1.0 - nu * nu) / E;
    const double eps_xx = nu * (1.0 + nu) * p / E;
    for (int n : m.node_set("top")) {
        EXPECT_NEAR(solver.displacement()[static_cast<std::size_t>(n * 2 + 1)], eps_yy * H, 1e-12);
    }
    for (int n : m.node_set("right")) {
        EXPECT_NEAR(solver.displacement()[static_cast<std::size_t>(n * 2 + 0)], eps_xx * W, 1e-12);
    }
    for (int e = 0; e < m.n_elements(); ++e) {
        for (int q = 0; q < 4; ++q) {
            const auto y = solver.state(e, q);
            EXPECT_NEAR(y[1], -p, 1e-9);
            EXPECT_NEAR(y[0], 0.0, 1e-9);
            EXPECT_NEAR(y[2], -nu * p, 1e-9); // plane strain: sigma_33 = nu (s11 + s22)
        }
    }
}

TEST(CompressionBlock, ConfinedColumnUnderRampedGravity) {
    const double W = 0.5, H = 3.0, rho = 1.8;
    const int ny = 6;
    Mesh m = rectangle_mesh({W, H, 1, ny});
    auto mat = material(LinearElasticParams{E, nu}, elastic_state());
    mat.density = rho;
    StaticSolver solver(m, {mat}, {});
    Stage st;
    st.steps = 2;
    st.displacements = {{"left", 0, 0.0}, {"right", 0, 0.0}, {"bottom", 1, 0.0}};
    st.gravity = GravityRamp{0.0, 10.0};
    std::vector<double> t_end;
    const auto res =
        solver.run_stage(st, [&](const IncrementInfo& info) { t_end.push_back(info.t_end); });
    ASSERT_TRUE(res.ok) << res.reason;
    ASSERT_EQ(t_end.size(), 2u);
    const double gamma = rho * 10.0;
    // Linear elements give a constant stress per element: the exact stress at mid-height.
    for (int e = 0; e < m.n_elements(); ++e) {
        const double y_mid = (e + 0.5) * H / ny;
        for (int q = 0; q < 4; ++q) {
            const auto y = solver.state(e, q);
            EXPECT_NEAR(y[1], -gamma * (H - y_mid), 1e-9) << "element " << e;
            EXPECT_NEAR(y[0], nu / (1.0 - nu) * y[1], 1e-9);
        }
    }
    // The bottom support carries the weight.
    EXPECT_NEAR(reaction(solver, "bottom", 1), gamma * H * W, 1e-9);
    EXPECT_EQ(solver.counters().gravity_load_builds, 1);
}
