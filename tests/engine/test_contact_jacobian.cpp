// The contact engine's Jacobian columns (paper Eq. 37: forward differences of the whole
// Algorithm 1 with theta = sqrt(EPS) per displacement component of slave and master) against
// central differences of the update itself, computed independently by calling interface_update
// with the inputs shifted in the engine's conventions (t_N = t_N0 + k_N delta g_N, gap
// g = x(1) - x(2), tangential increment master minus slave) and the base's sub-increment count.
//
// What to expect: Eq. 37 is a forward difference, so it carries a truncation error
// theta |f''| / 2. For the tangential rows the curvature scale is the tangential increment
// itself (the incrementally nonlinear models are not smooth at dg = 0), so the relative error is
// of order theta / |dg|: measured 3e-4 .. 1e-3 in 2D, up to 6.8e-3 in 3D where one tangential
// component is only ~1.2e-6 m (theta / 1.2e-6 = 1.2e-2). Tolerance 2e-2 (3x the largest
// measurement). The engine's central scheme (the slave and master lanes of one direction at
// +theta and -theta of the same gap component, their half difference) must agree with the
// reference to O(theta^2) (measured <= 6e-5 with fixed sub-increments, <= 2.7e-4 adaptive;
// tolerance 1e-3, still below Eq. 37's own truncation error), which checks the engine's sign
// and frame conventions far more tightly than Eq. 37 alone can.
//
// Noise: the differences see every discontinuity of the update within theta = 1.5e-8 m. Two
// were found with adaptive (few, large) sub-increments: the rate Newton Jacobian leaves a
// residual of ~1e-3 even after the polishing step, so the iteration count changes between
// lanes (jumps of 1.4e-2 kPa in tau, Sanisand, up to 40 % error in a column), and the model's
// own adaptive substep count changes between lanes (jumps ~ the model tolerance). The adaptive
// cases below therefore use the perturbation Newton Jacobian and a model tolerance of 1e-5.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#define IFSIM_TEST_ENGINE_HELPERS
#include "tests/engine/interface_fixtures.hpp"

using namespace ifsim;
using namespace ifsim::test;

TEST(ContactJacobian, Eq37MatchesCentralDifferencesHypoplasticity) {
    check_all_columns<Hypoplasticity>(l4c(0.9), hypo_state());
}

// Adaptive sub-increments with the default settings (rate Newton Jacobian, model tolerance
// 1e-3), hypoplasticity: Eq. 37 stays within its tolerance (measured <= 6.8e-3 for these two
// points, 2.3e-3 for a third point with dg = (1.6e-5, -1.6e-6) m in 2D). The central check is
// not asserted with these defaults: it is noise-dominated for some points (measured 1.9e-3 for
// that third point). Sanisand with these defaults is not asserted at all: a change of the
// Newton iteration count within theta gave 40 % in one column (see the note at the top).
TEST(ContactJacobian, AdaptiveDefaultsHypoplasticity) {
    for (const int ndim : {2, 3}) {
        ContactOptions opt;
        opt.interface.ndim = ndim;
        opt.interface.adaptive = true;
        const auto e = jacobian_errors<Hypoplasticity>(l4c(0.9), hypo_state(), ndim, opt);
        ASSERT_TRUE(e.ok);
        EXPECT_LT(e.eq37, kEq37Tol) << ndim;
        EXPECT_LT(e.normal, kNormalTol) << ndim;
    }
}

// A state sheared close to the peak (hypoplasticity, novel, 3D): the columns still match.
TEST(ContactJacobian, Eq37MatchesAfterShearing) {
    const auto mp = l4c(0.9);
    InterfaceSettings s;
    InterfaceState<double, Hypoplasticity::n_state> st;
    st.y = hypo_state();
    for (int i = 0; i < 10; ++i) {
        InterfaceStats<double> stats;
        interface_update<Hypoplasticity, double>(mp, s, st,
                                                 {-100.0, 2.0e-5, 0.0, -52.0, -47.0, 0.0}, stats);
        ASSERT_EQ(stats.status, lane_status::ok);
    }
    ASSERT_GT(st.y[3], 30.0);
    for (const int ndim : {2, 3}) {
        const auto e = jacobian_errors<Hypoplasticity>(
            mp, st.y, ndim, jacobian_options(InterfaceFormulation::novel, ndim, false));
        ASSERT_TRUE(e.ok);
        EXPECT_LT(e.eq37, kEq37Tol) << ndim;
        EXPECT_LT(e.central, kCentralTol) << ndim;
        EXPECT_LT(e.normal, kNormalTol) << ndim;
    }
}

// Coarse sub-increments (10x the paper's size). Hypoplasticity integrates each in one substep
// and the columns stay accurate. Sanisand's own adaptive substepping then changes its substep
// count between the base and a perturbed lane (Algorithm 1's sub-increments are pinned by the
// engine, the model's substeps are not), which puts jumps of ~2e-3 kPa into tau: divided by
// theta that is an error of up to 36 % in single columns at the default model tolerance
// (measured). With a model tolerance of 1e-5 the substep counts stay put and the columns agree
// (test_contact_jacobian_sanisand.cpp).
TEST(ContactJacobian, CoarseSubincrementsHypoplasticity) {
    for (const int ndim : {2, 3}) {
        auto opt = jacobian_options(InterfaceFormulation::novel, ndim, false);
        opt.interface.max_subincrement = 5.0e-5;
        const auto e = jacobian_errors<Hypoplasticity>(l4c(0.9), hypo_state(), ndim, opt);
        ASSERT_TRUE(e.ok);
        EXPECT_LT(e.eq37, kEq37Tol);
        EXPECT_LT(e.central, kCentralTol);
    }
}

// The scalar path gives the same columns as the SIMD path (the lanes of a batch are
// independent; xsimd and libm round differently, and theta amplifies that by 1/theta).
TEST(ContactJacobian, ScalarPathGivesTheSameColumns) {
    for (const int ndim : {2, 3}) {
        auto opt = jacobian_options(InterfaceFormulation::novel, ndim, false);
        opt.simd = false;
        const auto e = jacobian_errors<Hypoplasticity>(l4c(0.9), hypo_state(), ndim, opt);
        ASSERT_TRUE(e.ok);
        EXPECT_LT(e.eq37, kEq37Tol);
        EXPECT_LT(e.central, kCentralTol);
        EXPECT_LT(e.normal, kNormalTol);
    }
}

// The other two schemes keep the exact penalty row and finite tangential columns (on the
// tilted frame, two points, all lanes of the full scheme's fixed-point iterations). They are not
// the derivative of the update: Eq. B3 keeps only the first term of Eq. B2 (measured deviation
// from the central differences 4e-2 .. 3 relative); the full perturbation of Eqs. 39-40 starts
// its perturbed lanes from the committed state moved along the derivative of the end state,
// which the update (integrated from the committed state over the whole increment) already
// contains, so its tangential columns come out about twice the derivative (measured deviation
// 0.85 .. 2.6 relative).
TEST(ContactJacobian, OtherSchemesKeepThePenaltyRow) {
    for (const auto scheme : {ContactJacobian::analytical, ContactJacobian::full_perturbation}) {
        for (const int ndim : {2, 3}) {
            auto opt = jacobian_options(InterfaceFormulation::novel, ndim, false);
            opt.jacobian = scheme;
            const auto e =
                jacobian_errors<Hypoplasticity>(l4c(0.9), hypo_state(), ndim, opt, false);
            ASSERT_TRUE(e.ok);
            EXPECT_LT(e.normal, kNormalTol);
        }
    }
}
