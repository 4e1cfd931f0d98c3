// The solver's tangent check ([solver] check_tangent, fem/tangent_check.cpp) on the §5 shear box:
// it records every Newton iteration at two step sizes, splits each contact pair from the rest of
// the model, finds the tangent consistent where it is (the continuum's tangent, the pair's
// Eq. 37 columns at 100 kPa), and leaves the run as it would have been.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "tests/fem/fe_shear_box.hpp"

namespace ifsim::fem::testing {
namespace {

ShearBoxOptions box_options(bool check) {
    ShearBoxOptions o;
    o.steps = 5;
    o.displacement = 0.5e-3;
    o.check_tangent = check;
    return o;
}

TEST(TangentCheck, RecordsEveryIterationAndFindsTheShearBoxConsistent) {
    ShearBox box = build_shear_box(box_options(true));
    ASSERT_TRUE(box.solver->run_stage(box.consolidation).ok);
    ASSERT_TRUE(box.solver->run_stage(box.shear).ok);
    const auto& records = box.solver->tangent_checks();
    ASSERT_FALSE(records.empty());
    EXPECT_EQ(records.size(),
              2 * static_cast<std::size_t>(box.solver->counters().newton_iterations));
    std::vector<double> rest, pair;
    for (const TangentCheckRecord& r : records) {
        SCOPED_TRACE(r.iteration);
        ASSERT_EQ(r.pairs.size(), 1u);
        EXPECT_TRUE(std::isfinite(r.mismatch));
        EXPECT_GE(r.worst_dof, 0);
        // The first iterations of an increment start from a strain increment near zero, where
        // the intergranular strain's stiffness depends on the direction (not differentiable:
        // measured up to 0.68 for the continuum), and the first iteration after a re-gather
        // moves by a correction at the noise of the inner solves (the pair up to 0.37). The
        // typical iteration: continuum to 2e-7, the pair's Eq. 37 columns to 4e-4 (measured).
        if (r.iteration >= 3 && r.step < 1.0e-8) {
            rest.push_back(r.rest);
            pair.push_back(r.pairs[0]);
        }
    }
    ASSERT_GE(rest.size(), 10u);
    const auto median = [](std::vector<double> v) {
        std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
        return v[v.size() / 2];
    };
    EXPECT_LT(median(rest), 1.0e-5);
    EXPECT_LT(median(pair), 2.0e-3);
}

// The check evaluates the residual elsewhere and then restores the iterate: the run is the
// same bit for bit with and without it.
TEST(TangentCheck, LeavesTheRunUnchanged) {
    ShearBox with = build_shear_box(box_options(true));
    ShearBox without = build_shear_box(box_options(false));
    for (ShearBox* b : {&with, &without}) {
        ASSERT_TRUE(b->solver->run_stage(b->consolidation).ok);
        ASSERT_TRUE(b->solver->run_stage(b->shear).ok);
    }
    const auto& a = with.solver->displacement();
    const auto& b = without.solver->displacement();
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(a[i], b[i]) << i;
    }
}

} // namespace
} // namespace ifsim::fem::testing
