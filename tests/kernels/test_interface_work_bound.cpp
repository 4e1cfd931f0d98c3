// The work bound of Algorithm 1's adaptive sub-increments (InterfaceSettings::
// work_model_substeps, work_newton_iterations). The case is a real one: the costliest call of
// the coarse §6 Sanisand run's first wall increment (docs/large-scale-test.md, session 18), a
// rough band at the open threshold sheared 0.69 mm while t_N rises to -3.4 kPa. On the error
// control alone it takes 14 sub-increments of up to 150x the paper's size, each Sanisand
// evaluation over them 1 300 substeps (the cone cap) and each Newton 50 iterations, and it ends at
// the per-call work limit. Checked: the control law itself, step by step; that the bounded call
// succeeds at a small fraction of the work and agrees with the paper's fine fixed sub-increments;
// and that a SIMD lane takes the same decisions as the scalar path.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "tests/engine/interface_fixtures.hpp"

using namespace ifsim;
using namespace ifsim::test;

namespace {

constexpr int NS = Sanisand::n_state;
constexpr std::size_t W = simd::lanes;

// Rough point 48 of the coarse Sanisand run at (1.2, 0.0176, 1.0897), increment 8 (the first
// wall step), its state at the start of the increment in local axes.
InterfaceState<double, NS> touching_band() {
    const std::array<double, NS> y{-1.0002427296232068,
                                   -2.1427553239718944,
                                   -2.1167672030248399,
                                   -1.7553021272780995,
                                   -0.0021176855385196488,
                                   0.0,
                                   0.69439280449669116,
                                   -0.41782889886688851,
                                   0.21617463754597219,
                                   0.20165426132091632,
                                   0.97412583624881421,
                                   0.0011749991741025767,
                                   0.00031569370711735911,
                                   17.044460557407337,
                                   -8.8310232070869237,
                                   -8.2134373503204117,
                                   -39.77442084021181,
                                   -0.048100711837983937,
                                   -0.013336972492019849,
                                   -0.25,
                                   0.5,
                                   -0.25,
                                   0.0,
                                   0.0,
                                   0.0};
    InterfaceState<double, NS> st;
    for (int k = 0; k < NS; ++k) {
        st.y[k] = y[k];
    }
    st.eps_n = 0.02375380303284564;
    st.eps_p1 = 0.0056364782866527201;
    st.eps_p2 = -0.00041393435624226439;
    st.gamma1 = -0.057597558263150959;
    st.gamma2 = -6.0593312013148927e-05;
    st.last_subincrement = 151.89789734008926; // the gravity stages' large sub-increments
    return st;
}

// The call of the run's first Newton iteration of that increment.
InterfaceInput<double> first_wall_step() {
    return {-3.406367516156843,  -0.00068705348342443988, 8.4279967929396353e-07,
            -4.3831934950547611, -3.3164855085754326,     0.0};
}

InterfaceSettings the_run_settings() {
    InterfaceSettings s; // the scene's rough pair: novel 3D, adaptive, d_s = 6 mm, rate Jacobian
    s.adaptive = true;
    s.shear_band_thickness = 0.006;
    s.newton_switch_ratio = 0.5; // as the §6 Sanisand scene
    s.work_model_substeps = 0.0;
    s.work_newton_iterations = 0.0;
    return s;
}

InterfaceSettings bounded(double substeps, double iterations) {
    InterfaceSettings s = the_run_settings();
    s.work_model_substeps = substeps;
    s.work_newton_iterations = iterations;
    return s;
}

} // namespace

// Without the bound the call costs 127 k substeps (and without the Newton's switch too, it ends
// at the per-call work limit, as it did in the run); with it, it succeeds at a third of that and
// agrees with the paper's fixed sub-increments refined five times (measured: 890 sub-increments and
// 44 k substeps against 111 k and 223 k; stresses 4e-5 kPa apart).
TEST(InterfaceWorkBound, SanisandBandAtItsConeSucceedsAtAFractionOfTheWork) {
    const auto mp = karlsruhe_sanisand(1.0);
    const auto in = first_wall_step();
    // On the rate Newton alone (as in the run) the call ends at the work limit; with the
    // Newton's switch to the perturbation Jacobian it succeeds at 127 k substeps.
    InterfaceSettings rate_only = the_run_settings();
    rate_only.newton_switch_ratio = 0.0;
    const auto failed = direct_update<Sanisand>(mp, rate_only, touching_band(), in);
    ASSERT_EQ(failed.stats.status, lane_status::failed);
    EXPECT_EQ(failed.stats.cause, interface_failure::work_limit);
    const auto unbounded = direct_update<Sanisand>(mp, the_run_settings(), touching_band(), in);
    ASSERT_EQ(unbounded.stats.status, lane_status::ok);

    const InterfaceSettings s = bounded(8.0, 4.0);
    const auto r = direct_update<Sanisand>(mp, s, touching_band(), in);
    ASSERT_EQ(r.stats.status, lane_status::ok);
    EXPECT_LT(r.stats.model_substeps, 0.05 * s.max_model_substeps);
    EXPECT_LT(r.stats.model_substeps, 0.5 * unbounded.stats.model_substeps);
    // The average evaluation stays near the bound (the first sub-increments, started from the
    // carried size, are larger).
    EXPECT_LT(r.stats.model_substeps / r.stats.evaluations, 4.0 * s.work_model_substeps);

    InterfaceSettings fine = the_run_settings();
    fine.adaptive = false;
    fine.max_subincrement = 1.0e-6;
    const auto ref = direct_update<Sanisand>(mp, fine, touching_band(), in);
    ASSERT_EQ(ref.stats.status, lane_status::ok);
    const double scale = std::abs(in.t_N);
    for (int k = 0; k < 5; ++k) {
        EXPECT_LT(std::abs(r.st.y[k] - ref.st.y[k]), s.adaptive_tolerance * scale)
            << "stress " << k << ": " << r.st.y[k] << " against " << ref.st.y[k];
    }
    // The band's dilation over the increment (measured: 7e-8 of 0.032 apart).
    const double dilation = ref.st.eps_n - touching_band().eps_n;
    EXPECT_LT(std::abs(r.st.eps_n - ref.st.eps_n), 1.0e-3 * std::abs(dilation))
        << r.st.eps_n << " against " << ref.st.eps_n;
}

// The control law, step by step: after an accepted sub-increment whose evaluations took S
// substeps on average, the next size is at most target / S times the one just taken (within
// the floor of 0.2 of the step doubling). Without the bound the same call grows past it.
TEST(InterfaceWorkBound, NextSubincrementShrinksWithTheSubstepsPerEvaluation) {
    const auto mp = karlsruhe_sanisand(1.0);
    const auto in = first_wall_step();
    auto run = [&](const InterfaceSettings& s, double target) {
        auto c = interface_begin<Sanisand, double>(s, touching_band(), in);
        int checked = 0;
        int grown_past = 0;
        while (c.active && c.count < 5000) {
            const double hl = std::min(c.h, 1.0 - c.t);
            const double t0 = c.t;
            const double evaluations = c.stats.evaluations;
            const double substeps = c.stats.model_substeps;
            const double fallbacks = c.stats.newton_fallbacks;
            interface_step<Sanisand, double>(mp, s, c);
            const bool accepted = c.t > t0;
            if (!accepted || !c.active || c.stats.newton_fallbacks != fallbacks) {
                continue;
            }
            const double per_evaluation =
                (c.stats.model_substeps - substeps) / (c.stats.evaluations - evaluations);
            const double bound = hl * std::max(0.2, target / std::max(per_evaluation, 1.0));
            ++checked;
            if (c.h > bound * (1.0 + 1.0e-12)) {
                ++grown_past;
            }
        }
        return std::pair{checked, grown_past};
    };
    const auto [checked, grown_past] = run(bounded(8.0, 0.0), 8.0);
    EXPECT_GT(checked, 20);
    EXPECT_EQ(grown_past, 0);
    // The same law read against the unbounded control: it does grow past it.
    const auto [checked_free, grown_free] = run(the_run_settings(), 8.0);
    EXPECT_GT(checked_free, 0);
    EXPECT_GT(grown_free, 0);
}

// The bounded call in one lane of a SIMD batch whose other lanes are ordinary bands: the lane
// takes the scalar path's sub-increments (the decisions are per lane) and ends at its state up to
// the round-off of xsimd's transcendental functions.
TEST(InterfaceWorkBound, BatchLaneMatchesScalar) {
    if (W < 2) {
        GTEST_SKIP() << "scalar build";
    }
    const auto mp = karlsruhe_sanisand(1.0);
    const InterfaceSettings s = bounded(8.0, 4.0);
    const std::size_t hard = W - 1;
    std::array<InterfaceState<double, NS>, W> lanes;
    std::array<InterfaceInput<double>, W> inputs;
    for (std::size_t l = 0; l < W; ++l) {
        if (l == hard) {
            lanes[l] = touching_band();
            inputs[l] = first_wall_step();
        } else {
            lanes[l].y = sanisand_state(-50.0 - 10.0 * static_cast<double>(l), 0.5, 0.75);
            const double t_N = -55.0 - 10.0 * static_cast<double>(l);
            inputs[l] = {t_N, 2.0e-4, -3.0e-5, 0.5 * t_N, 0.55 * t_N, 0.0};
        }
    }
    const auto [st, stats] = batched_update<Sanisand>(
        mp, s, [&](std::size_t l) { return lanes[l]; }, [&](std::size_t l) { return inputs[l]; });
    for (std::size_t l = 0; l < W; ++l) {
        const auto scalar = direct_update<Sanisand>(mp, s, lanes[l], inputs[l]);
        ASSERT_EQ(simd::lane(stats.status, l), scalar.stats.status) << "lane " << l;
        EXPECT_EQ(simd::lane(stats.subincrements, l), scalar.stats.subincrements) << "lane " << l;
        for (int k = 0; k < 5; ++k) {
            EXPECT_NEAR(simd::lane(st.y[k], l), scalar.st.y[k], 1.0e-9 * std::abs(scalar.st.y[0]))
                << "lane " << l << " stress " << k;
        }
    }
}
