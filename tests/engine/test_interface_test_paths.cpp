// The point-level interface test on its different execution paths and discretisations: SIMD
// against scalar, one thread against two, the sub-increment size (observed order of
// convergence of t_t1 at a fixed plate displacement) and the Algorithm 1 tolerance.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include <tbb/global_control.h>

#define IFSIM_TEST_ENGINE_HELPERS
#include "tests/engine/interface_fixtures.hpp"

using namespace ifsim;
using namespace ifsim::test;

namespace {

bool same_bits(double a, double b) {
    return std::memcmp(&a, &b, sizeof(double)) == 0;
}

double t_t1_at_end(const InterfaceTestSpec& spec) {
    const DriverRun r = run_driver(spec);
    EXPECT_TRUE(r.result.ok) << r.result.reason;
    EXPECT_EQ(r.result.counters.step_cuts, 0); // a cut changes the path, not the discretisation
    return r.rows.back().t_t1;
}

} // namespace

// 0.5 mm in 10 steps through the peak, the SIMD kernels (contact lanes and the sample) against
// the scalar ones: the step Newton takes the same iterations and ends within round-off amplified
// by the finite-difference tangents (measured |delta t_t1| <= 1.4e-8 kPa novel, 1.4e-10 kPa
// Stutz; 2.6e-8 and 6.4e-8 kPa over 1 mm in 20 steps).
TEST(InterfaceTestPaths, SimdMatchesScalar) {
    for (const auto f : {InterfaceFormulation::novel, InterfaceFormulation::stutz}) {
        InterfaceTestSpec spec = l4c_spec(f);
        spec.stages = {{10, 5.0e-4, 0.0}};
        const DriverRun a = run_driver(spec);
        spec.contact.simd = false;
        spec.sample_update.simd = false;
        const DriverRun b = run_driver(spec);
        ASSERT_TRUE(a.result.ok) << a.result.reason;
        ASSERT_TRUE(b.result.ok) << b.result.reason;
        ASSERT_EQ(a.rows.size(), b.rows.size());
        for (std::size_t k = 0; k < a.rows.size(); ++k) {
            SCOPED_TRACE(k);
            EXPECT_EQ(a.rows[k].newton_iterations, b.rows[k].newton_iterations);
            EXPECT_NEAR(a.rows[k].t_t1, b.rows[k].t_t1, 1.0e-6);
            EXPECT_NEAR(a.rows[k].slip1, b.rows[k].slip1, 1.0e-7 * a.rows[k].slip1 + 1.0e-15);
            EXPECT_NEAR(a.rows[k].eps_n, b.rows[k].eps_n, 1.0e-9);
        }
    }
}

// The contact engine runs its lanes under TBB: 1 and 2 threads give bitwise the same rows.
TEST(InterfaceTestPaths, ThreadCountDoesNotChangeTheResult) {
    InterfaceTestSpec spec = l4c_spec(InterfaceFormulation::novel);
    spec.stages = {{10, 5.0e-4, 0.0}};
    auto with_threads = [&](int n) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, n);
        return run_driver(spec);
    };
    const DriverRun one = with_threads(1);
    const DriverRun two = with_threads(2);
    ASSERT_TRUE(one.result.ok);
    ASSERT_EQ(one.rows.size(), two.rows.size());
    for (std::size_t k = 0; k < one.rows.size(); ++k) {
        const InterfaceRow& a = one.rows[k];
        const InterfaceRow& b = two.rows[k];
        for (const auto& [x, y] :
             {std::pair{a.t_t1, b.t_t1}, std::pair{a.t_n, b.t_n}, std::pair{a.slip1, b.slip1},
              std::pair{a.eps_n, b.eps_n}, std::pair{a.eps_p1, b.eps_p1}, std::pair{a.s_p1, b.s_p1},
              std::pair{a.u_n, b.u_n}, std::pair{a.e_interface, b.e_interface}}) {
            EXPECT_TRUE(same_bits(x, y)) << "row " << k << ": " << x << " vs " << y;
        }
        EXPECT_EQ(a.newton_iterations, b.newton_iterations);
    }
}

// Sub-increment size: t_t1 at u_t1 = 0.3 mm (6 steps, before the peak) for max_subincrement
// 5e-5, 2.5e-5, 1.25e-5, Stutz. With one model substep per sub-increment the error is that of
// the model's Heun step, second order: observed order from the three runs 1.87 (measured;
// against a fine reference see long_test_interface_test.cpp).
TEST(InterfaceTestPaths, SubincrementSizeConvergesAtSecondOrder) {
    InterfaceTestSpec spec = l4c_spec(InterfaceFormulation::stutz);
    spec.stages = {{6, 3.0e-4, 0.0}};
    spec.newton_tolerance = 1.0e-8; // step equations solved well below the differences
    double t[3];
    const double sizes[3] = {5.0e-5, 2.5e-5, 1.25e-5};
    for (int i = 0; i < 3; ++i) {
        spec.contact.interface.max_subincrement = sizes[i];
        t[i] = t_t1_at_end(spec);
    }
    const double d1 = t[0] - t[1], d2 = t[1] - t[2];
    ASSERT_GT(std::abs(d2), 1.0e-7) << "differences below the step tolerance";
    const double order = std::log2(d1 / d2);
    EXPECT_GT(order, 1.5) << t[0] << " " << t[1] << " " << t[2];
    EXPECT_LT(order, 2.5) << t[0] << " " << t[1] << " " << t[2];
    EXPECT_LT(std::abs(d1), 1.0e-4); // 2e-6 of t_t1
}

// Algorithm 1's tolerance with one polishing step: the result does not depend on it (measured
// within 5e-6 kPa for 1e-2 .. 1.25e-4, both formulations), because the polished residual is of
// order tol^2 or below the step tolerance. (The paper's rule without polishing is erratic here:
// errors of 1e-2 .. 2e-2 kPa, step cuts, and no convergence of the novel test at tol = 2e-3 with
// sub-increments of 5e-5 -- measured, not asserted.)
TEST(InterfaceTestPaths, PolishedResultDoesNotDependOnTheTolerance) {
    for (const auto f : {InterfaceFormulation::novel, InterfaceFormulation::stutz}) {
        InterfaceTestSpec spec = l4c_spec(f);
        spec.stages = {{6, 3.0e-4, 0.0}};
        spec.newton_tolerance = 1.0e-8;
        double ref = 0.0;
        for (const double tol : {1.0e-2, 2.0e-3, 2.5e-4}) {
            spec.contact.interface.tolerance = tol;
            const double t = t_t1_at_end(spec);
            if (tol == 1.0e-2) {
                ref = t;
            }
            EXPECT_NEAR(t, ref, 2.0e-5) << "tolerance " << tol;
        }
    }
}
