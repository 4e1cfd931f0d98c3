// Sanisand right after a load reversal with alpha beyond the bounding surface (b:n < 0): h sits
// at its cap and the loading denominator at its floor. The plastic rate must still keep the
// state on the cone (the consistency condition), and the evaluation the rough segment of the
// fine §6 run stalled in (p = 4 kPa, tau/p = 1.6, |z| = 45; docs/large-scale-test.md, "State
// after session 20") must finish in a modest number of substeps, independent of how the
// increment is split, and lane by lane the same on the SIMD path.
//
// Before the hardening coefficient followed the floored denominator, alpha moved by O(1) over a
// substep of ~1e-15 strain, the drift correction put it back, and the evaluation stalled at the
// smallest substep until its attempt budget (200 000) ran out.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "kernels/material_update.hpp"
#include "kernels/sanisand.hpp"
#include "tests/kernels/sanisand_test_support.hpp"

using namespace ifsim;

namespace {

using namespace sanisand_test;

// Model state and strain increment of the stalled evaluation (sub-increment 8 of the replay
// /work/runs/s19rep/fine-costliest-s19.toml), dumped from the kernel at full precision.
Y stalled_state() {
    return {-3.5097755122175176,    -4.5198360395635415,    -4.0270810017035563,
            -6.372458438355415,     0.00052835601441308293, 0.0,
            0.65073269885248775,    -0.13253180070835696,   0.10874791666698483,
            0.023783884041372137,   1.5643334676920622,     0.00019391880943454525,
            2.3620702155406593e-05, 13.74782825634688,      -13.632692619174481,
            -0.11513563717239908,   -40.109729076657757,    0.027145168505449343,
            0.00060393356675502363, -0.13256289661703094,   0.10870286629226894,
            0.023860030324762003,   1.5643925275972521,     0.00019504447954791165,
            2.3703209790487374e-05};
}
Sym<double> stalled_increment() {
    return {-5.368688645663577e-07,  7.3153701894023555e-06,  3.484650868593482e-06,
            -1.7667188645140924e-06, -5.4680880449540209e-09, 0.0};
}

// Triaxial compression at eta = q/p = 2.4, beyond the bounding ratio M_b = 1.81 (p = 50 kPa,
// e = 0.65, psi = -0.25), on the cone with alpha_in = alpha: a fresh reversal. b is along n.
Y triaxial_beyond_bound() {
    const double p = 50.0, q = 2.4 * p;
    Y y = Sanisand::initial_state(
        {-(p + 2.0 * q / 3.0), -(p - q / 3.0), -(p - q / 3.0), 0.0, 0.0, 0.0}, 0.65);
    const Sym<double> r = sym_at(y, Sanisand::alpha_index);
    const Sym<double> n = voigt::scale(r, 1.0 / voigt::norm(r));
    const Sym<double> alpha = voigt::axpy(r, -sanisand::sqrt_2_3 * karlsruhe().m, n);
    set_sym_at(y, Sanisand::alpha_index, alpha);
    set_sym_at(y, Sanisand::alpha_in_index, alpha);
    return y;
}
// Further axial compression (compression negative).
Sym<double> axial_compression(double d) {
    return {-d, 0.5 * d, 0.5 * d, 0.0, 0.0, 0.0};
}

UpdateStats<double> step(const SanisandParams& P, Y& y, const Sym<double>& de,
                         const IntegrationSettings& s) {
    UpdateStats<double> st;
    material_update<Sanisand, double>(P, s, {}, y, de, st);
    return st;
}

Y after_increment(const SanisandParams& P, const IntegrationSettings& s, const Y& y,
                  const Sym<double>& de) {
    const Y dy = sanisand::increment(P, s, y, de, true);
    Y yn = y;
    for (int i = 0; i < Sanisand::n_state; ++i) {
        yn[i] += dy[i];
    }
    return yn;
}

// The premise: beyond the bounding surface, h capped, the denominator floored.
TEST(SanisandReversalBeyondBound, StateIsBeyondTheBoundWithTheDenominatorFloored) {
    const auto P = karlsruhe();
    const IntegrationSettings s;
    const Y y = triaxial_beyond_bound();
    const auto q = sanisand::point(P, s, y);
    const auto k = sanisand::plastic(P, q, y);
    EXPECT_NEAR(q.f, 0.0, 1e-12);
    EXPECT_GT(sanisand::loading_numerator(q, k, voigt::scale(axial_compression(1e-6), -1.0)), 0.0);
    EXPECT_LT(voigt::ddot(k.b, q.n), -0.1);
    EXPECT_LE(k.h_denom, sanisand::h_denominator_min);
    const double den_raw = k.Kp + 2.0 * q.G * k.n_Rdev - q.K * k.D * k.N;
    const double den = sanisand::loading_denominator(q, k);
    EXPECT_LT(den_raw, 0.0);
    EXPECT_GT(den, 0.0);
    // the hardening coefficient that belongs to the floor: p n:dalpha = L Kp_floored
    const double h = sanisand::consistent_h(q, k, den);
    EXPECT_LT(h, 1e-6 * k.h);
    EXPECT_NEAR((2.0 / 3.0) * q.p * h * voigt::ddot(k.b, q.n), k.Kp + den - den_raw,
                1e-9 * std::fabs(den_raw - k.Kp));
}

// The Euler increment leaves f = 0 only to second order in the strain, and alpha moves at a
// rate of the order of the elastic ratio rate 2G/p.
TEST(SanisandReversalBeyondBound, PlasticRateStaysOnTheCone) {
    const auto P = karlsruhe();
    const IntegrationSettings s;
    const Y y = triaxial_beyond_bound();
    const auto q = sanisand::point(P, s, y);
    double f_prev = 0.0;
    for (double size : {1e-6, 1e-7, 1e-8}) {
        const Y yn = after_increment(P, s, y, axial_compression(size));
        const double f = std::fabs(sanisand::yield_ratio(P, s, yn));
        const double d_alpha = voigt::norm(
            voigt::sub(sym_at(yn, Sanisand::alpha_index), sym_at(y, Sanisand::alpha_index)));
        EXPECT_LT(d_alpha, 100.0 * (2.0 * q.G / q.p) * size) << "size " << size;
        EXPECT_LT(f, 0.01 * d_alpha) << "size " << size;
        if (f_prev > 0.0) {
            EXPECT_LT(f, 0.02 * f_prev) << "not second order at size " << size;
        }
        f_prev = f;
    }
}

// The stalled evaluation: finishes with status ok in few substeps, on the cone, and one step
// agrees with the same strain in 20 steps.
TEST(SanisandReversalBeyondBound, StalledEvaluationFinishesAndIsSplitIndependent) {
    const auto P = karlsruhe();
    const IntegrationSettings s = contact_model_integration();
    const Sym<double> de = stalled_increment();
    Y one = stalled_state();
    const auto st = step(P, one, de, s);
    EXPECT_EQ(st.status, lane_status::ok);
    EXPECT_LT(st.substeps + st.rejected, 2000.0);
    EXPECT_NEAR(sanisand::yield_ratio(P, s, one), 0.0, 1e-12);
    Y many = stalled_state();
    for (int i = 0; i < 20; ++i) {
        const auto si = step(P, many, voigt::scale(de, 1.0 / 20.0), s);
        EXPECT_EQ(si.status, lane_status::ok);
    }
    const double scale = voigt::norm(stress_of(many));
    EXPECT_LT(voigt::norm(voigt::sub(stress_of(one), stress_of(many))), 2e-3 * scale);
    EXPECT_LT(voigt::norm(voigt::sub(sym_at(one, Sanisand::alpha_index),
                                     sym_at(many, Sanisand::alpha_index))),
              2e-3 * voigt::norm(sym_at(many, Sanisand::alpha_index)));
}

// The SIMD path (the engine's) takes the stalled evaluation as the scalar path does, lane by
// lane, with the triaxial state in the other lanes.
TEST(SanisandReversalBeyondBound, SimdLanesMatchTheScalarPath) {
    const auto P = karlsruhe();
    const IntegrationSettings s = contact_model_integration();
    std::array<Y, W> ys;
    std::array<Sym<double>, W> ds;
    for (std::size_t l = 0; l < W; ++l) {
        ys[l] = l % 2 == 0 ? stalled_state() : triaxial_beyond_bound();
        ds[l] = l % 2 == 0 ? stalled_increment() : axial_compression(1e-5);
    }
    YB yb = pack_states(ys);
    const Sym<Batch> db = pack_increments(ds);
    UpdateStats<Batch> sb;
    material_update<Sanisand, Batch>(P, s, {}, yb, db, sb);
    for (std::size_t l = 0; l < W; ++l) {
        Y ref = ys[l];
        const auto st = step(P, ref, ds[l], s);
        EXPECT_EQ(simd::lane(sb.status, l), st.status) << "lane " << l;
        for (int k = 0; k < Sanisand::n_state; ++k) {
            EXPECT_NEAR(simd::lane(yb[k], l), ref[k], 1e-9 * (1.0 + std::fabs(ref[k])))
                << "lane " << l << " entry " << k;
        }
    }
}

} // namespace
