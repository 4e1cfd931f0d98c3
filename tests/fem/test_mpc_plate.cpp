// The rigid top plate (equal vertical displacement of a node set, by elimination) on a block of
// two elastic materials side by side, and linear springs to ground on the plate (constant
// normal stiffness), against closed-form answers.
//
// The two materials share lambda but differ in G, so under the plate the exact solution is
// u_x = 0 and a uniform vertical strain eps with sigma_yy = (lambda + 2 G_i) eps: the plate
// load is the mean constrained modulus times eps.
#include <gtest/gtest.h>

#include <algorithm>

#include "tests/fem/fem_test_support.hpp"

using namespace ifsim;
using namespace ifsim::fem;
using namespace ifsim::fem::testing;

namespace {

constexpr double W = 2.0, H = 1.0;
constexpr double lambda = 4000.0;
constexpr double G_soft = 4000.0, G_stiff = 8000.0;
constexpr double M_mean = 0.5 * ((lambda + 2.0 * G_soft) + (lambda + 2.0 * G_stiff));

LinearElasticParams from_lame(double lam, double G) {
    return {G * (3.0 * lam + 2.0 * G) / (lam + G), lam / (2.0 * (lam + G))};
}

StaticSolver two_material_block() {
    Mesh m = rectangle_mesh({W, H, 4, 2});
    for (int e = 0; e < m.n_elements(); ++e) {
        m.element_sets[e % 4 < 2 ? "soft" : "stiff"].push_back(e);
    }
    return StaticSolver(m,
                        {material(from_lame(lambda, G_soft), elastic_state(), "soft"),
                         material(from_lame(lambda, G_stiff), elastic_state(), "stiff")},
                        {});
}

Stage confined(double p_from, double p_to, bool plate) {
    Stage st;
    st.displacements = {{"left", 0, 0.0}, {"right", 0, 0.0}, {"bottom", 1, 0.0}};
    if (plate) {
        st.equal_displacements = {{"top", 1}};
    }
    st.pressures = {{"top", p_from, p_to}};
    return st;
}

std::vector<double> top_uy(const StaticSolver& s) {
    std::vector<double> v;
    for (int n : s.mesh().node_set("top")) {
        v.push_back(s.displacement()[static_cast<std::size_t>(n * 2 + 1)]);
    }
    return v;
}

} // namespace

TEST(RigidPlate, TopNodesMoveTogetherWithTheExactSettlement) {
    auto solver = two_material_block();
    const double p = 100.0;
    ASSERT_TRUE(solver.run_stage(confined(0.0, p, true)).ok);
    const auto uy = top_uy(solver);
    const double expected = -p / M_mean * H;
    for (double u : uy) {
        EXPECT_NEAR(u, expected, 1e-12);
    }
    for (int n = 0; n < solver.mesh().n_nodes(); ++n) {
        EXPECT_NEAR(solver.displacement()[static_cast<std::size_t>(n * 2)], 0.0, 1e-12);
    }
    const double eps = expected / H;
    for (int e = 0; e < solver.mesh().n_elements(); ++e) {
        const double G = e % 4 < 2 ? G_soft : G_stiff;
        EXPECT_NEAR(solver.state(e, 0)[1], (lambda + 2.0 * G) * eps, 1e-9);
        EXPECT_NEAR(solver.state(e, 0)[0], lambda * eps, 1e-9);
    }
    // The plate's equation carries the whole load: internal forces sum to p W.
    double sum = 0.0;
    for (int n : solver.mesh().node_set("top")) {
        sum += solver.internal_force()[static_cast<std::size_t>(n * 2 + 1)];
    }
    EXPECT_NEAR(sum, -p * W, 1e-9);
}

TEST(RigidPlate, WithoutThePlateTheTopDoesNotSettleEvenly) {
    auto solver = two_material_block();
    ASSERT_TRUE(solver.run_stage(confined(0.0, 100.0, false)).ok);
    const auto uy = top_uy(solver);
    const auto [lo, hi] = std::minmax_element(uy.begin(), uy.end());
    EXPECT_GT(*hi - *lo, 0.1 * std::abs(*lo)); // the soft half settles more
}

TEST(GroundSpring, PlateOnASpringSharesTheLoad) {
    auto solver = two_material_block();
    const double p = 100.0, k = 5.0e4; // kN/m per m thickness, the whole plate
    Stage st = confined(0.0, p, true);
    st.springs = {{"top", 1, k}};
    ASSERT_TRUE(solver.run_stage(st).ok);
    const double delta = -p * W / (M_mean * W / H + k);
    for (double u : top_uy(solver)) {
        EXPECT_NEAR(u, delta, 1e-12);
    }
}

TEST(GroundSpring, ReferenceIsTheDisplacementWhereTheSpringStarts) {
    auto solver = two_material_block();
    const double k = 5.0e4;
    ASSERT_TRUE(solver.run_stage(confined(0.0, 100.0, true)).ok); // no spring yet
    const double u1 = top_uy(solver).front();
    Stage hold = confined(100.0, 100.0, true);
    hold.springs = {{"top", 1, k}};
    ASSERT_TRUE(solver.run_stage(hold).ok); // the spring starts unloaded: nothing moves
    EXPECT_NEAR(top_uy(solver).front(), u1, 1e-14);
    Stage more = confined(100.0, 150.0, true);
    more.springs = hold.springs; // the same spring continues
    ASSERT_TRUE(solver.run_stage(more).ok);
    const double u3 = top_uy(solver).front();
    EXPECT_NEAR(u3 - u1, -50.0 * W / (M_mean * W / H + k), 1e-12);
    ASSERT_TRUE(solver.run_stage(confined(150.0, 150.0, true)).ok); // spring removed
    EXPECT_NEAR(top_uy(solver).front(), -150.0 / M_mean * H, 1e-12);
}
