// Algorithm 1's Newton keeps the iterate that met its tolerance when the polishing correction
// after it leaves the tolerance (kernels/interface_newton.hpp). The case is the costliest call
// of the fine §6 Sanisand run's first wall step (docs/large-scale-test.md, session 19): a rough
// band held at 147 equal sub-increments, t_N -7.2 kPa, 0.12 mm of slip, with the Broyden switch
// of the scene. A Broyden polishing step jumped from a met iterate (r = 1.6e-3) to a tensile
// strain where the band's stress is zero (r = 1.0), and that iterate was taken: a held
// sub-increment has no error check, so the band went on from sigma_N = 0, and every later
// sub-increment failed until the work limit (1.5 M model substeps on the SIMD path). Checked:
// every accepted sub-increment meets the normal targets to the Newton tolerance, on the scalar
// path and on a lone SIMD lane as the engine runs it, and both end where the call ends on the
// perturbation Jacobian.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "tests/engine/interface_fixtures.hpp"

using namespace ifsim;
using namespace ifsim::test;

namespace {

constexpr int NS = Sanisand::n_state;
using Batch = simd::batch;

// Rough point 86 at (1.2, 0.0894, 0.6951), the fine run's first wall step.
InterfaceState<double, NS> held_band() {
    const std::array<double, NS> y{-4.3863708084191941,
                                   -8.8646651874192219,
                                   -4.8069364323894872,
                                   -5.9889840774986975,
                                   0.052319529269141185,
                                   0.0,
                                   0.64504246928391828,
                                   -0.25927378921171862,
                                   0.46335765342016261,
                                   -0.20408386420844404,
                                   0.96823926487219969,
                                   -0.0085736042070871862,
                                   -2.2077017745371791e-05,
                                   7.6878478420914922,
                                   -12.406869104433818,
                                   4.7190212623423253,
                                   -28.462584314772407,
                                   0.23066763388690403,
                                   -0.00096698380329626006,
                                   -0.25000000000015049,
                                   0.50000000000009459,
                                   -0.24999999999994413,
                                   -1.0873809868590222e-12,
                                   2.0314857202136068e-14,
                                   0.0};
    InterfaceState<double, NS> st;
    for (int k = 0; k < NS; ++k) {
        st.y[k] = y[k];
    }
    st.eps_n = 0.00026464518551439864;
    st.eps_p1 = -0.00072785924578799572;
    st.eps_p2 = -0.00011868711665701776;
    st.gamma1 = -0.0033537854856914378;
    st.gamma2 = 3.3521861862824015e-05;
    return st;
}

InterfaceInput<double> held_call() {
    return {-7.1922547642156696, 0.00011611344704059095, 1.3565287899506948e-05,
            -8.8644456821562851, -4.8072491032708271,    147.0};
}

InterfaceSettings the_scene_settings() {
    // The rough pair of scenes/large-shear/large-shear-novel-sanisand.toml as it was when
    // the bug showed (sessions 18-27: with the switch to Broyden updates, where the polishing
    // correction is a Broyden step).
    InterfaceSettings s;
    s.adaptive = true;
    s.shear_band_thickness = 0.006;
    s.work_model_substeps = 8.0;
    s.work_newton_iterations = 4.0;
    s.newton_switch_ratio = 0.5;
    return s;
}

// Reads lane 0 of a batch lane back into a scalar one.
struct FirstLane {
    void operator()(Batch& b, double& v) const { v = simd::lane(b, 0); }
    void operator()(simd::batch_mask& b, bool& v) const {
        v = simd::lane(simd::select(b, Batch(1.0), Batch(0.0)), 0) > 0.5;
    }
};

// Relative residual of the normal stresses against their targets at fraction t (as the
// Newton measures it).
double normal_residual(const Algorithm1Lane<double, NS>& c, double t) {
    double r2 = 0.0, ref2 = 0.0;
    for (int i = 0; i < 3; ++i) {
        const double target = c.target_start[i] + (c.target_end[i] - c.target_start[i]) * t;
        r2 += (c.cur.y[i] - target) * (c.cur.y[i] - target);
        ref2 += target * target;
    }
    return std::sqrt(r2) / std::max(std::sqrt(ref2), 1.0e-3);
}

struct Stepped {
    InterfaceState<double, NS> st;
    InterfaceStats<double> stats;
    int accepted = 0;
    double worst_residual = 0.0; // over the accepted sub-increments
};

// The call stepped on the scalar path, or on lane 0 of a SIMD batch whose other lanes are idle
// copies (as engine/contact_lanes.hpp's run_lanes_packed runs a lone lane), checking each accepted
// sub-increment.
Stepped step_call(const InterfaceSettings& s, bool on_simd) {
    const auto mp = karlsruhe_sanisand(1.0);
    Stepped out;
    out.st = held_band();
    auto one = interface_begin<Sanisand, double>(s, out.st, held_call());
    auto check = [&](const Algorithm1Lane<double, NS>& lane, double t_before) {
        if (lane.t > t_before) {
            ++out.accepted;
            out.worst_residual = std::max(out.worst_residual, normal_residual(lane, lane.t));
        }
    };
    if (on_simd) {
        Algorithm1Lane<Batch, NS> c;
        zip_fields(c, one, [](auto& b, auto& v) { b = std::remove_reference_t<decltype(b)>(v); });
        alignas(64) bool used[simd::lanes] = {};
        used[0] = true;
        c.active = c.active && simd::batch_mask::load_aligned(used);
        while (simd::any(c.active)) {
            const double t_before = simd::lane(c.t, 0);
            interface_step<Sanisand, Batch>(mp, s, c);
            zip_fields(c, one, FirstLane{});
            check(one, t_before);
        }
    } else {
        while (one.active) {
            const double t_before = one.t;
            interface_step<Sanisand, double>(mp, s, one);
            check(one, t_before);
        }
    }
    interface_end<Sanisand, double>(s, one, out.st, out.stats);
    return out;
}

} // namespace

TEST(InterfacePolishGuard, HeldBandMeetsItsTargetsInEverySubincrement) {
    const InterfaceSettings s = the_scene_settings();
    InterfaceSettings by_difference = s;
    by_difference.newton_jacobian = NewtonJacobian::perturbation;
    by_difference.newton_switch_ratio = 0.0;
    const Stepped ref = step_call(by_difference, false);
    ASSERT_EQ(ref.stats.status, lane_status::ok);
    for (const bool on_simd : {false, true}) {
        const Stepped r = step_call(s, on_simd);
        ASSERT_EQ(r.stats.status, lane_status::ok) << "simd " << on_simd;
        EXPECT_GE(r.accepted, 147) << "simd " << on_simd;
        // Before the guard, one sub-increment was taken at r = 1.0 (sigma_N = 0).
        EXPECT_LT(r.worst_residual, s.tolerance) << "simd " << on_simd;
        EXPECT_LT(r.stats.model_substeps, 0.05 * s.max_model_substeps) << "simd " << on_simd;
        // The shear and in-plane stresses where the perturbation Newton ends them, to the
        // Newton tolerance of the 7-9 kPa stresses.
        for (int k = 0; k < 5; ++k) {
            EXPECT_NEAR(r.st.y[k], ref.st.y[k], 10.0 * s.tolerance * std::abs(held_call().t_N))
                << "simd " << on_simd << " stress " << k;
        }
    }
}

// With no polishing step the result is the iterate that met the tolerance, so the guard leaves
// the paper's stopping rule (polish_iterations = 0) as it was: every accepted sub-increment
// meets its targets, and the call ends near the polished one.
TEST(InterfacePolishGuard, PaperStoppingRuleMeetsItsTargetsToo) {
    InterfaceSettings s = the_scene_settings();
    const Stepped polished = step_call(s, false);
    s.polish_iterations = 0;
    const Stepped paper = step_call(s, false);
    ASSERT_EQ(paper.stats.status, lane_status::ok);
    EXPECT_LT(paper.worst_residual, s.tolerance);
    for (int k = 0; k < 5; ++k) {
        EXPECT_NEAR(paper.st.y[k], polished.st.y[k], 10.0 * s.tolerance * std::abs(held_call().t_N))
            << "stress " << k;
    }
}
