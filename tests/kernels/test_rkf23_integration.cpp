// Tests of the default substepping (kernels/explicit_integration.hpp): Runge-Kutta-Fehlberg
// 2(3) with the intergranular strain integrated on its own inside each substep, and the
// substep size carried from one update to the next.

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "kernels/parameter_sets.hpp"
#include "tests/kernels/element_paths.hpp"

namespace ifsim {
namespace {

using test::HypoState;

HypoplasticityParams karlsruhe(bool igs) {
    HypoplasticityParams p = parameter_sets::hypoplasticity_karlsruhe();
    p.intergranular_strain = igs;
    p.prepare();
    return p;
}

double stress_error(const HypoState& a, const HypoState& ref) {
    return voigt::norm(voigt::sub(stress_of(a), stress_of(ref))) / voigt::norm(stress_of(ref));
}

Sym<double> direction() {
    const Sym<double> d{-0.8, 0.3, 0.25, 0.35, -0.1, 0.2};
    return voigt::scale(d, 1.0 / voigt::norm(d));
}

// Start state with h = h_along * R along the increment's direction.
HypoState start(const HypoplasticityParams& p, double h_along) {
    return test::hypo_state({-150.0, -90.0, -80.0, 12.0, -6.0, 4.0}, 0.75,
                            voigt::scale(direction(), h_along * p.R));
}

HypoState integrate(const HypoplasticityParams& p, IntegrationSettings s, HypoState y, double size,
                    double fixed = 0.0, UpdateStats<double>* stats = nullptr) {
    s.max_substeps = 1 << 22;
    const UpdateStats<double> st =
        test::strain_step(p, s, y, voigt::scale(direction(), size), fixed);
    if (stats != nullptr) {
        *stats = st;
    }
    return y;
}

// Fixed substeps on smooth problems (no intergranular strain, or h mobilised along the
// increment) converge at third order, at three rate evaluations per substep.
TEST(Rkf23Integration, FixedSubstepsConvergeAtThirdOrder) {
    IntegrationSettings s;
    s.split_internal = false;
    for (const bool igs : {false, true}) {
        const HypoplasticityParams p = karlsruhe(igs);
        const HypoState y0 = start(p, 1.0);
        const HypoState ref = integrate(p, s, y0, 1e-2, 16384.0);
        std::vector<double> errs;
        for (int n = 128; n <= 1024; n *= 2) {
            UpdateStats<double> st;
            const HypoState y = integrate(p, s, y0, 1e-2, n, &st);
            EXPECT_EQ(st.substeps, n);
            EXPECT_EQ(st.rate_evaluations, 3.0 * n);
            errs.push_back(stress_error(y, ref));
        }
        for (std::size_t i = 1; i < errs.size(); ++i) {
            const double order = std::log2(errs[i - 1] / errs[i]);
            EXPECT_GT(order, 2.8) << "igs " << igs << " i " << i;
            EXPECT_LT(order, 3.3) << "igs " << igs << " i " << i;
        }
    }
}

// h on its own and h with the stress integrate the same equations: at a tight tolerance both
// reach the same state, from h = 0 and after a full reversal (the non-smooth starts).
TEST(Rkf23Integration, SplitAndCoupledHAgreeAtATightTolerance) {
    const HypoplasticityParams p = karlsruhe(true);
    for (const double h_along : {0.0, -1.0, 0.3}) {
        IntegrationSettings s;
        s.tolerance = 1e-9;
        s.split_internal = false;
        const HypoState coupled = integrate(p, s, start(p, h_along), 1e-3);
        s.split_internal = true;
        const HypoState split = integrate(p, s, start(p, h_along), 1e-3);
        EXPECT_LT(stress_error(split, coupled), 1e-7) << "h " << h_along;
        for (int k = 0; k < 6; ++k) {
            EXPECT_NEAR(split[Hypoplasticity::h_index + k], coupled[Hypoplasticity::h_index + k],
                        1e-7 * p.R)
                << "h " << h_along << " component " << k;
        }
    }
}

// The default scheme's error follows its tolerance on the non-smooth starts (within a small
// factor: the control is local), and it needs fewer rate evaluations than h integrated with
// the stress to the same tolerance.
TEST(Rkf23Integration, SplitErrorFollowsTheToleranceAndCostsLess) {
    const HypoplasticityParams p = karlsruhe(true);
    for (const double h_along : {0.0, -1.0}) {
        IntegrationSettings s;
        s.tolerance = 1e-10;
        s.split_internal = false;
        const HypoState ref = integrate(p, s, start(p, h_along), 2e-3);
        for (double tol = 1e-3; tol >= 0.99e-6; tol /= 10.0) {
            s.tolerance = tol;
            s.split_internal = true;
            UpdateStats<double> split_stats, coupled_stats;
            const HypoState y = integrate(p, s, start(p, h_along), 2e-3, 0.0, &split_stats);
            EXPECT_EQ(split_stats.status, lane_status::ok);
            // measured: 0.3 .. 3.5 tol (local control; h's own error feeds the stress)
            EXPECT_LT(stress_error(y, ref), 5.0 * tol) << "tol " << tol << " h " << h_along;
            s.split_internal = false;
            integrate(p, s, start(p, h_along), 2e-3, 0.0, &coupled_stats);
            EXPECT_LT(split_stats.rate_evaluations, coupled_stats.rate_evaluations)
                << "tol " << tol << " h " << h_along;
        }
    }
}

// While h : de < 0 (unloading) h moves linearly, dh = de: the kink at the switch ends a step
// of h's sub-integration, so an increment that stays short of it gives h0 + de exactly.
TEST(Rkf23Integration, UnloadingShortOfTheSwitchMovesHLinearly) {
    const HypoplasticityParams p = karlsruhe(true);
    const HypoState y0 = start(p, -1.0); // h = -R along the increment: switch after R
    const double size = 0.6 * p.R;
    UpdateStats<double> st;
    const HypoState y = integrate(p, IntegrationSettings{}, y0, size, 0.0, &st);
    const Sym<double> de = voigt::scale(direction(), size);
    for (int k = 0; k < 6; ++k) {
        EXPECT_NEAR(y[Hypoplasticity::h_index + k], y0[Hypoplasticity::h_index + k] + de[k], 1e-15)
            << k;
    }
}

// The carried substep: an update stores the size its step control would take next (as a strain
// norm); the next update of the same size starts from it and skips the rejections of a start
// with the whole increment, at the same accuracy.
TEST(Rkf23Integration, CarriedSubstepSavesTheRejectionsOfTheNextUpdate) {
    const HypoplasticityParams p = karlsruhe(false);
    IntegrationSettings s;
    s.tolerance = 1e-6;
    HypoState y = start(p, 0.0);
    UpdateStats<double> first, second, cold;
    y = integrate(p, s, y, 1e-2, 0.0, &first);
    const double carried = y[Hypoplasticity::substep_index];
    EXPECT_GT(first.rejected, 0.0);
    EXPECT_GT(carried, 0.0);
    EXPECT_LT(carried, 1e-2);
    const HypoState warm = integrate(p, s, y, 1e-2, 0.0, &second);
    s.carry_substep = false;
    const HypoState fresh = integrate(p, s, y, 1e-2, 0.0, &cold);
    EXPECT_LT(second.rejected, cold.rejected);
    EXPECT_LE(second.rate_evaluations, cold.rate_evaluations);
    EXPECT_LT(stress_error(warm, fresh), 10.0 * s.tolerance);
    // fixed substeps neither use nor change it
    UpdateStats<double> fixed;
    const HypoState f = integrate(p, IntegrationSettings{}, y, 1e-2, 4.0, &fixed);
    EXPECT_EQ(f[Hypoplasticity::substep_index], carried);
}

} // namespace
} // namespace ifsim
