// Results do not depend on the number of threads: 1 and 2 threads give bitwise identical
// displacements, states and internal forces (fixed chunks, coloured scatter, serial sums).
#include <gtest/gtest.h>

#include <cstring>

#include <tbb/global_control.h>

#include "tests/fem/fem_test_support.hpp"

using namespace ifsim;
using namespace ifsim::fem;
using namespace ifsim::fem::testing;

namespace {

struct Snapshot {
    std::vector<double> u;
    std::vector<double> f;
    std::vector<double> states;
    long iterations = 0;
};

Snapshot run(int threads, Integration integration) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                              static_cast<std::size_t>(threads));
    Mesh m = box_mesh({1.0, 1.0, 1.0, 5, 4, 5});
    distort(m, 0.1, 0.2);
    auto mat = material(karlsruhe(), hypo_state({-50, -50, -50, 0, 0, 0}, 0.7));
    mat.density = 1.7;
    mat.k0 = K0Stress{1.0, 17.0, 50.0, 0.5};
    SolverSettings s;
    s.integration = integration;
    s.element_grain = 4;        // many tasks per colour
    s.update.chunk_points = 64; // many constitutive chunks
    StaticSolver solver(m, {mat}, s);
    Stage st;
    st.steps = 2;
    st.displacements = {{"bottom", 0, 0.0}, {"bottom", 1, 0.0}, {"bottom", 2, 0.0},
                        {"left", 0, 0.0},   {"right", 0, 0.0},  {"front", 1, 0.0},
                        {"back", 1, 0.0}};
    st.equal_displacements = {{"top", 2}};
    st.pressures = {{"top", 50.0, 150.0}};
    st.gravity = GravityRamp{10.0, 10.0};
    const auto res = solver.run_stage(st);
    EXPECT_TRUE(res.ok) << res.reason;
    Snapshot snap{
        solver.displacement(), solver.internal_force(), {}, solver.counters().newton_iterations};
    for (int e = 0; e < m.n_elements(); ++e) {
        for (int q = 0; q < solver.points_per_element(); ++q) {
            const auto y = solver.state(e, q);
            snap.states.insert(snap.states.end(), y.begin(), y.end());
        }
    }
    return snap;
}

bool bitwise_equal(const std::vector<double>& a, const std::vector<double>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

} // namespace

TEST(Threads, OneAndTwoThreadsGiveBitwiseIdenticalResults) {
    for (Integration integ : {Integration::full, Integration::reduced}) {
        const Snapshot one = run(1, integ);
        const Snapshot two = run(2, integ);
        EXPECT_GT(one.iterations, 2);
        EXPECT_GT(max_abs(one.u), 1e-4);
        EXPECT_EQ(one.iterations, two.iterations);
        EXPECT_TRUE(bitwise_equal(one.u, two.u));
        EXPECT_TRUE(bitwise_equal(one.f, two.f));
        EXPECT_TRUE(bitwise_equal(one.states, two.states));
    }
}
