// The early cut of a diverged Newton solve (SolverSettings::divergence_check): the rule on
// residual sequences, and through the solver a step too large for Newton that the early
// cut solves with fewer iterations and the same result.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "fem/newton_divergence.hpp"
#include "tests/fem/fem_test_support.hpp"

using namespace ifsim;
using namespace ifsim::fem;
using namespace ifsim::fem::testing;

namespace {

// The first index at which the rule cuts the solve that starts at `start`, or -1.
int first_cut(const std::vector<double>& r, std::size_t start = 0) {
    for (std::size_t n = 1; n <= r.size(); ++n) {
        if (newton_diverged(std::span<const double>(r.data(), n), start)) {
            return static_cast<int>(n) - 1;
        }
    }
    return -1;
}

} // namespace

TEST(NewtonDivergence, ConvergingAndSlowSolvesAreNotCut) {
    EXPECT_EQ(first_cut({1e-2, 3e-4, 2e-7, 1e-12}), -1);
    // A slow linear rate and a wandering start that ends below where it started.
    std::vector<double> slow{1e-2};
    for (int k = 0; k < 19; ++k) {
        slow.push_back(slow.back() * 0.9);
    }
    EXPECT_EQ(first_cut(slow), -1);
    EXPECT_EQ(first_cut({5e-2, 0.7, 0.7, 0.3, 0.1, 0.09, 4e-2, 1e-3}), -1);
    // A stall below the start (the stagnation acceptance's business, not this rule's).
    EXPECT_EQ(first_cut({1e-3, 2e-5, 2.4e-5, 2.2e-5, 2.3e-5, 2.5e-5, 2.2e-5, 2.4e-5}), -1);
}

TEST(NewtonDivergence, CutsASolveStillAboveItsStartAfterSixIterations) {
    // The fine §6 Stutz run's stage-2 increment before the rule: 20 iterations near 0.7-0.99.
    const std::vector<double> r{4.9e-2, 0.69, 0.11, 0.70, 0.69, 0.69, 0.69, 0.35, 0.54};
    EXPECT_EQ(first_cut(r), 6);
    // Above the start before the 6th iteration is allowed.
    EXPECT_EQ(first_cut({1e-2, 0.5, 0.4, 0.3, 0.2, 5e-3}), -1);
    // A NaN residual counts as diverged.
    EXPECT_EQ(first_cut({1e-2, 1e-3, 1e-3, 1e-3, 1e-3, 1e-3, std::nan("")}), 6);
}

TEST(NewtonDivergence, CountsFromTheStartOfTheCurrentSolve) {
    // A re-gather at index 4 starts a new solve from 1e-4: the earlier, larger residuals do
    // not count, and its own 6 iterations do.
    const std::vector<double> r{1e-2, 1e-4, 1e-7, 1e-10, 1e-4, 3e-4, 2e-4, 2e-4, 2e-4, 2e-4, 2e-4};
    EXPECT_EQ(first_cut(r, 4), 10);
    EXPECT_EQ(first_cut(r, 0), -1);
}

namespace {

// A hypoplastic block under 60/30 kPa sheared by `shear` m (block height 1 m) in one step.
StageRun shear_in_one_step(bool divergence_check, double shear) {
    Mesh m = box_mesh({1.0, 0.5, 1.0, 2, 1, 2});
    distort(m, 0.1, 0.5);
    SolverSettings s;
    s.divergence_check = divergence_check;
    s.max_cuts = 10;
    Stage st;
    st.steps = 1;
    st.displacements = {{"bottom", 0, 0.0}, {"bottom", 1, 0.0}, {"bottom", 2, 0.0},
                        {"front", 1, 0.0},  {"back", 1, 0.0},   {"top", 0, shear}};
    st.equal_displacements = {{"top", 2}};
    st.pressures = {{"top", 60.0, 60.0}, {"left", 30.0, 30.0}, {"right", 30.0, 30.0}};
    return run_hypoplastic_stage(m, hypo_state({-30, -30, -60, 0, 0, 0}, 0.65), s, st);
}

} // namespace

TEST(NewtonDivergence, SolverCutsEarlyAndReachesTheSameState) {
    // 2 % shear in one step: the full step and its first halvings do not converge. Without
    // the rule a diverged attempt runs all 20 iterations; with it, 6. The cut sequence is the
    // same, so the committed state is too.
    const StageRun on = shear_in_one_step(true, 0.02);
    const StageRun off = shear_in_one_step(false, 0.02);
    ASSERT_TRUE(on.result.ok) << on.result.reason;
    ASSERT_TRUE(off.result.ok) << off.result.reason;
    std::printf("early cut: %ld iterations, %ld cuts (%ld early); without: %ld, %ld\n",
                on.counters.newton_iterations, on.counters.cuts, on.counters.divergence_cuts,
                off.counters.newton_iterations, off.counters.cuts);
    EXPECT_GE(on.counters.divergence_cuts, 1);
    EXPECT_EQ(off.counters.divergence_cuts, 0);
    EXPECT_EQ(on.counters.cuts, off.counters.cuts);
    EXPECT_LE(on.counters.newton_iterations + 10, off.counters.newton_iterations);
    for (int i = 0; i < 6; ++i) {
        EXPECT_NEAR(on.stress[i], off.stress[i], 1e-9 * std::abs(off.stress[2])) << i;
    }
}
