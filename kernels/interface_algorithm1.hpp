#pragma once
// Algorithm 1 of the paper (§3.5): a continuum model M used as interface model. The shear
// strain increment (Eq. 25) is split into sub-increments; inside each, a Newton iteration on the
// interface normal strains (Eqs. 21-23, kernels/interface_newton.hpp) drives the interface
// normal stresses to their targets (Eqs. 18-20: sigma_N = t_N and, for the novel formulation,
// sigma_p1/p2 = extrapolated continuum stress), with the shear stresses of the last converged
// state carried along (Eqs. 24, 27). The model is called unchanged through material_update(),
// so any constitutive model of the material engine plugs in.
//
// Per lane: own number of sub-increments, own Newton convergence (masks); a lane that fails
// (Newton not converged, model failure, band collapse) keeps its start state and reports
// status failed so the caller can cut the increment.
//
// The algorithm is split into interface_begin (set-up), interface_step (one sub-increment) and
// interface_end (result) around a carried Algorithm1Lane, so that an engine can gather lanes
// from anywhere into a SIMD batch (engine/contact_lanes.hpp). A lane's arithmetic depends only
// on its own data: it gives the same bits in any slot and next to any neighbours.

#include <array>

#include "kernels/interface_newton.hpp"
#include "kernels/interface_settings.hpp"
#include "kernels/material_update.hpp"

namespace ifsim {

// What the sub-increment loop carries from one sub-increment to the next.
template <class T, int NS>
struct Algorithm1Lane {
    using Mask = simd::mask_t<T>;
    InterfaceState<T, NS> cur; // state after the last accepted sub-increment
    InterfaceStats<T> stats;
    std::array<T, 3> target_start{}, target_end{};
    std::array<T, 3> x_rate{}; // normal strain increment per unit fraction
    T dgam1 = T(0.0), dgam2 = T(0.0), total = T(0.0);
    T h = T(1.0), t = T(0.0), last_h = T(1.0);
    T h0 = T(1.0); // the first sub-increment size, where a second try starts again
    T cause = T(0.0);
    T count = T(0.0); // sub-increments tried (guard max_subincrements)
    Mask finite_in{}, below{}, open{}, run{}, forced{}, active{}, failed{};
    Mask perturbed{}; // on its second try: Newton on the perturbation Jacobian
};

// Calls f(a_field, b_field) for every field of two carries (of different value types, e.g. a
// batch and one lane); the engine moves lanes in and out of batches with it.
template <class A, class B, class F>
void zip_fields(A& a, B& b, F&& f) {
    for (std::size_t k = 0; k < a.cur.y.size(); ++k) {
        f(a.cur.y[k], b.cur.y[k]);
    }
    f(a.cur.eps_n, b.cur.eps_n);
    f(a.cur.eps_p1, b.cur.eps_p1);
    f(a.cur.eps_p2, b.cur.eps_p2);
    f(a.cur.gamma1, b.cur.gamma1);
    f(a.cur.gamma2, b.cur.gamma2);
    f(a.cur.last_subincrement, b.cur.last_subincrement);
    f(a.stats.status, b.stats.status);
    f(a.stats.subincrements, b.stats.subincrements);
    f(a.stats.newton_iterations, b.stats.newton_iterations);
    f(a.stats.evaluations, b.stats.evaluations);
    f(a.stats.model_substeps, b.stats.model_substeps);
    f(a.stats.residual, b.stats.residual);
    f(a.stats.open, b.stats.open);
    f(a.stats.cause, b.stats.cause);
    f(a.stats.band_clamped, b.stats.band_clamped);
    f(a.stats.newton_fallbacks, b.stats.newton_fallbacks);
    for (int c = 0; c < 3; ++c) {
        f(a.target_start[c], b.target_start[c]);
        f(a.target_end[c], b.target_end[c]);
        f(a.x_rate[c], b.x_rate[c]);
    }
    f(a.dgam1, b.dgam1);
    f(a.dgam2, b.dgam2);
    f(a.total, b.total);
    f(a.h, b.h);
    f(a.t, b.t);
    f(a.last_h, b.last_h);
    f(a.h0, b.h0);
    f(a.cause, b.cause);
    f(a.count, b.count);
    f(a.finite_in, b.finite_in);
    f(a.below, b.below);
    f(a.open, b.open);
    f(a.run, b.run);
    f(a.forced, b.forced);
    f(a.active, b.active);
    f(a.failed, b.failed);
    f(a.perturbed, b.perturbed);
}

template <class T>
T band_floor(const InterfaceSettings& s) {
    return T(s.min_band_fraction * s.shear_band_thickness);
}

// Set-up of one evaluation: band thickness, shear strain increment, targets and the first
// sub-increment size. Lanes that do not run (open, invalid input, collapsed band) start
// inactive.
template <class M, class T>
Algorithm1Lane<T, M::n_state> interface_begin(const InterfaceSettings& s,
                                              const InterfaceState<T, M::n_state>& st,
                                              const InterfaceInput<T>& in) {
    using Mask = simd::mask_t<T>;
    constexpr int NS = M::n_state;
    const int k = interface_unknowns(s);
    Algorithm1Lane<T, NS> c;

    c.finite_in = simd::isfinite(in.t_N) && simd::isfinite(in.dg1) && simd::isfinite(in.dg2) &&
                  simd::isfinite(in.s_p1) && simd::isfinite(in.s_p2) && state_finite<T, NS>(st.y);
    // Eq. 26: band thickness following the interface normal strain.
    const T d_s_eq26 = s.shear_band_thickness * (1.0 + st.eps_n);
    c.below = !(d_s_eq26 > band_floor<T>(s));
    const Mask band_ok = s.clamp_band ? Mask(true) : !c.below;
    const T d_s = simd::select(c.below, band_floor<T>(s), d_s_eq26);
    // Contact open (t_N above -open_threshold). Below the threshold the models' stiffness
    // vanishes with the stress and Algorithm 1 cannot follow t_N, so a touching point
    // (-threshold < t_N < 0) integrates its band at sigma_N = -threshold, and the caller scales
    // its tractions down by |t_N| / threshold: its shear still answers slip, and with the
    // Stutz formulation it is the closed band's at the threshold. A separated point
    // (t_N >= 0) keeps its state and transmits nothing.
    c.open = in.t_N > -s.open_threshold;
    const Mask separated = !(in.t_N < 0.0);
    c.run = c.finite_in && band_ok && !separated;
    const Mask touching = c.open && !separated;

    // Eq. 25: tan(delta gamma) = delta g_T / d_s.
    const T safe_ds = simd::select(band_ok, d_s, T(s.shear_band_thickness));
    c.dgam1 = simd::select(c.run, simd::atan(in.dg1 / safe_ds), T(0.0));
    c.dgam2 = (s.ndim == 2) ? T(0.0) : simd::select(c.run, simd::atan(in.dg2 / safe_ds), T(0.0));
    c.total = simd::max(simd::abs(c.dgam1), simd::abs(c.dgam2));

    // Targets of Eqs. 18-20 are met at the end of the increment; the sub-increments in between
    // follow a straight path from the start values (sigma_N, sigma_p1, sigma_p2 of the converged
    // state), so a change of t_N or of the continuum stress is spread over the sub-increments
    // instead of being forced into the first one.
    // A touching novel band integrates at sigma_N = -threshold. Near t_N = 0 it keeps the
    // in-plane stress ratio of its state (the continuum's in-plane stresses scaled up with
    // t_N moved its targets with every change of t_N: a band at its limit surface answered a
    // perturbation of t_N with a kink). At the threshold it must meet the closed band, whose
    // targets are the continuum's sigma_p (Eqs. 19-20): a switch there made sigma_p, and the
    // shear with it, jump, and the global Newton of a wall whose points sit near -1 kPa fell
    // to a linear rate (docs/large-scale-test.md). So over -1 ... -1/2 x threshold the
    // touching targets blend from the continuum's, scaled to -threshold, to the band's own
    // ratio with a smoothstep weight (C1 in t_N). Closed bands keep the continuum's targets
    // bit for bit. A state without compression (sigma_N > -1e-3 threshold, e.g. a band
    // started from a stress-free continuum) has no ratio of its own and takes isotropic ones.
    const T thr = T(s.open_threshold);
    const Mask own_ratio = st.y[0] < T(-1.0e-3) * thr;
    const T ratio_scale = thr / simd::select(own_ratio, -st.y[0], thr);
    const T u = simd::min(simd::max(T(2.0) + T(2.0) * in.t_N / thr, T(0.0)), T(1.0));
    const T w = u * u * (T(3.0) - T(2.0) * u);
    const Mask blended = touching && w < T(1.0);
    const T up_scale = thr / simd::max(-in.t_N, T(0.5) * thr);
    auto in_plane = [&](const T& own_y, const T& continuum) {
        const T own = simd::select(own_ratio, own_y * ratio_scale, -thr);
        const T mix = w * own + (T(1.0) - w) * continuum * up_scale;
        return simd::select(touching, simd::select(blended, mix, own), continuum);
    };
    c.target_end = {simd::select(touching, -thr, in.t_N), in_plane(st.y[1], in.s_p1),
                    in_plane(st.y[2], in.s_p2)};
    c.target_start = {st.y[0], st.y[1], st.y[2]};
    // Sub-increments needed for the change of the normal targets: at most max_normal_change of
    // the stress per sub-increment (a change of t_N without shear would otherwise be one step).
    T dtarget = T(0.0);
    T tnorm = T(0.0);
    for (int i = 0; i < k; ++i) {
        dtarget = simd::max(dtarget, simd::abs(c.target_end[i] - c.target_start[i]));
        tnorm += c.target_end[i] * c.target_end[i];
    }
    tnorm = simd::max(simd::sqrt(tnorm), T(1.0));
    const T n_normal =
        simd::select(c.run, simd::ceil(dtarget / (s.max_normal_change * tnorm)), T(1.0));

    // Sub-increment size as a fraction of the increment. Fixed: n_sub = ceil(total / max).
    c.forced = in.forced_subincrements > 0.5;
    const T n_fixed = simd::select(
        c.forced, in.forced_subincrements,
        simd::max(simd::max(simd::ceil(c.total / s.max_subincrement), n_normal), T(1.0)));
    c.h = 1.0 / n_fixed;
    if (s.adaptive && !simd::all(c.forced)) {
        // Start from the last accepted size (in units of max_subincrement) or the paper's size.
        const T last = simd::select(st.last_subincrement > 0.0, st.last_subincrement, T(1.0));
        const T frac = last * s.max_subincrement / simd::max(c.total, T(1.0e-300));
        const T h0 = simd::min(T(1.0), simd::select(c.total > 0.0, frac, T(1.0)));
        c.h = simd::select(c.forced, c.h, simd::min(h0, 1.0 / simd::max(n_normal, T(1.0))));
    }

    c.cur = st;
    c.last_h = c.h;
    c.h0 = c.h;
    c.perturbed = Mask(false);
    c.active = c.run;
    c.failed = !c.finite_in || !band_ok;
    c.cause = simd::select(!c.finite_in, T(interface_failure::non_finite_input),
                           simd::select(!band_ok, T(interface_failure::band_collapse), T(0.0)));
    return c;
}

// One sub-increment (Algorithm 1 lines 2-13) for the active lanes; the others are unchanged.
// A lane becomes inactive when it reaches the end of the increment or fails.
template <class M, class T>
void interface_step(const typename M::Params& mp, const InterfaceSettings& s,
                    Algorithm1Lane<T, M::n_state>& c) {
    using Mask = simd::mask_t<T>;
    constexpr int NS = M::n_state;
    const int k = interface_unknowns(s);
    // Forced lanes (uniform sub-increments) give the same result on either branch; the step
    // doubling runs only when some lane needs it.
    const bool adaptive = s.adaptive && simd::any(c.active && !c.forced);
    auto target_at = [&](const T& frac) {
        std::array<T, 3> tg;
        for (int i = 0; i < 3; ++i) {
            tg[i] = c.target_start[i] + (c.target_end[i] - c.target_start[i]) * frac;
        }
        return tg;
    };
    // Records the first reason a lane fails.
    auto fail = [&](const Mask& m, double code) {
        c.cause = simd::select(m && !c.failed, T(code), c.cause);
        c.failed = c.failed || m;
    };
    const Mask tried = c.active;
    const T hl = simd::select(c.active, simd::min(c.h, T(1.0) - c.t), T(0.0));
    std::array<T, 3> guess;
    for (int i = 0; i < 3; ++i) {
        guess[i] = c.x_rate[i] * hl;
    }
    const T t_end = simd::select(hl >= (T(1.0) - c.t), T(1.0), c.t + hl);
    // A lane's second try (InterfaceSettings::newton_fallback): lanes that would fail on a
    // Newton that did not converge start again from their last accepted state at their first
    // sub-increment size, on the perturbation Jacobian. Returns the lanes that take it.
    const bool second_tries = s.newton_fallback && s.newton_jacobian == NewtonJacobian::rate;
    auto second_try = [&](const Mask& would_fail) {
        const Mask m = second_tries ? (would_fail && !c.perturbed) : Mask(false);
        c.perturbed = c.perturbed || m;
        c.stats.newton_fallbacks += simd::select(m, T(1.0), T(0.0));
        return m;
    };
    const T iterations_before = c.stats.newton_iterations;
    const T evaluations_before = c.stats.evaluations;
    const T substeps_before = c.stats.model_substeps;
    const auto full = solve_subincrement<M, T>(mp, s, c.cur.y, guess, c.dgam1 * hl, c.dgam2 * hl,
                                               target_at(t_end), c.active, c.stats, c.perturbed);
    const T full_iterations = c.stats.newton_iterations - iterations_before;
    Mask accept = c.active && full.converged;
    StateVec<T, NS> y_new = full.y;
    std::array<T, 3> x_new = full.x;
    T next_h = c.h;
    if (adaptive) {
        // Step doubling: two half sub-increments against the full one.
        const T hh = 0.5 * hl;
        std::array<T, 3> g2;
        for (int i = 0; i < 3; ++i) {
            g2[i] = 0.5 * full.x[i];
        }
        const auto a = solve_subincrement<M, T>(mp, s, c.cur.y, g2, c.dgam1 * hh, c.dgam2 * hh,
                                                target_at(c.t + hh), accept && !c.forced, c.stats,
                                                c.perturbed);
        // Forced lanes run neither half (a is masked off for them and reports converged).
        const auto b =
            solve_subincrement<M, T>(mp, s, a.y, a.x, c.dgam1 * hh, c.dgam2 * hh, target_at(t_end),
                                     accept && a.converged && !c.forced, c.stats, c.perturbed);
        const Mask both = accept && a.converged && b.converged;
        // Error of the shear stresses (the normal ones are pinned by Eqs. 18-20).
        const T dt1 = b.y[3] - full.y[3];
        const T dt2 = b.y[4] - full.y[4];
        const T scale = simd::max(voigt::norm(stress_of(b.y)), T(1.0e-3));
        const T err = simd::sqrt(dt1 * dt1 + dt2 * dt2) / scale;
        const Mask accurate = (err <= s.adaptive_tolerance) || c.forced;
        const T q = 0.9 * simd::sqrt(s.adaptive_tolerance / simd::max(err, T(1.0e-30)));
        // Forced lanes (uniform sub-increments) take the full sub-increment as it is.
        accept = simd::select_mask(c.forced, accept, both && accurate);
        y_new = select_state<T, NS>(c.forced, full.y, b.y);
        for (int i = 0; i < 3; ++i) {
            x_new[i] = simd::select(c.forced, full.x[i], a.x[i] + b.x[i]);
        }
        T grow = simd::min(T(4.0), simd::max(T(0.2), q));
        // The work bound (InterfaceSettings::work_newton_iterations, work_model_substeps):
        // both counts grow with the sub-increment, so the ratio target / measured scales it.
        if (s.work_newton_iterations > 0.0) {
            grow =
                simd::min(grow, T(s.work_newton_iterations) / simd::max(full_iterations, T(1.0)));
        }
        if (s.work_model_substeps > 0.0) {
            const T evaluations = simd::max(c.stats.evaluations - evaluations_before, T(1.0));
            const T per_evaluation = (c.stats.model_substeps - substeps_before) / evaluations;
            grow = simd::min(grow, T(s.work_model_substeps) / simd::max(per_evaluation, T(1.0)));
        }
        grow = simd::max(T(0.2), grow);
        const T shrink = simd::select(both, simd::max(T(0.2), simd::min(q, T(0.5))), T(0.25));
        // Forced lanes keep their size and halve it where Newton fails (forced_step_size).
        next_h = simd::select(c.forced, simd::select(accept, c.h, 0.5 * hl),
                              simd::select(accept, hl * grow, hl * shrink));
        // A sub-increment that cannot be made small enough ends the lane as failed, or where a
        // Newton failed, gives it its second try.
        const Mask smallest = c.active && !accept && (hl * c.total < s.min_subincrement);
        const Mask retried = second_try(smallest && !both);
        const Mask too_small = smallest && !retried;
        next_h = simd::select(retried, c.h0, next_h);
        // The cause and number of the first of the three solves that failed (the full one, or
        // a half whose Newton failed where the full one converged), else the error control's.
        const Mask ran = c.active && full.converged; // the halves ran where this holds
        const Mask a_ok = a.converged || !(ran && !c.forced);
        const Mask b_ok = b.converged || !(ran && a.converged && !c.forced);
        const Mask fa = !full.converged, fh = !fa && !a_ok, fb = !fa && !fh && !b_ok;
        const Mask model_failed =
            (fa && full.model_failed) || (fh && a.model_failed) || (fb && b.model_failed);
        const Mask singular = (fa && full.singular) || (fh && a.singular) || (fb && b.singular);
        fail(too_small && model_failed, interface_failure::model);
        fail(too_small && singular, interface_failure::singular_newton);
        fail(too_small && !both, interface_failure::newton);
        fail(too_small, interface_failure::error_control);
        const T failed_residual = simd::select(
            fa, full.residual, simd::select(fh, a.residual, simd::select(fb, b.residual, err)));
        c.stats.residual = simd::select(too_small, failed_residual, c.stats.residual);
        c.active = c.active && !too_small;
    } else if (s.adaptive) {
        // Only forced lanes in this batch: the Jacobian lanes of an adaptive run. They take the
        // base's count of equal sub-increments, which need not be integrable where the base
        // took unequal ones (a first sub-increment across a reversal): a sub-increment whose
        // Newton fails is halved and the lane goes on at that size. The decision depends only
        // on the lane's own data, and the reference lane (the base re-run on this
        // discretisation) and its perturbations almost always split at the same places, so
        // their differences stay derivatives of one discretisation. Failing them instead
        // dropped their point's Jacobian columns (docs/large-scale-test.md).
        const Mask retry = c.active && !full.converged && (hl * c.total >= s.min_subincrement);
        const Mask retried = second_try(c.active && !full.converged && !retry);
        c.h = simd::select(retry, 0.5 * hl, simd::select(retried, c.h0, c.h));
        const Mask ends = c.active && !retry && !retried;
        fail(ends && full.model_failed, interface_failure::model);
        fail(ends && full.singular, interface_failure::singular_newton);
        fail(ends && !full.converged, interface_failure::newton);
        c.active = c.active && (full.converged || retry || retried);
    } else {
        // Fixed sub-increments: the second try solves the same sub-increment again.
        const Mask retried = second_try(c.active && !full.converged);
        const Mask ends = c.active && !retried;
        fail(ends && full.model_failed, interface_failure::model);
        fail(ends && full.singular, interface_failure::singular_newton);
        fail(ends && !full.converged, interface_failure::newton);
        c.active = c.active && (full.converged || retried);
    }
    // Eq. 26 within the increment: a sub-increment that takes d_s below its floor ends the
    // lane (band collapse) unless the floor is to be held.
    if (!s.clamp_band) {
        const Mask collapses =
            accept && !(s.shear_band_thickness * (1.0 + c.cur.eps_n + x_new[0]) > band_floor<T>(s));
        fail(collapses, interface_failure::band_collapse);
        accept = accept && !collapses;
        c.active = c.active && !collapses;
    }
    // Algorithm 1 lines 11-13: save strain, state and stress of the converged sub-increment.
    y_new[5] = T(0.0); // Eq. 17: no t1-t2 shear in the interface
    c.cur.y = select_state<T, NS>(accept, y_new, c.cur.y);
    c.cur.eps_n = simd::select(accept, c.cur.eps_n + x_new[0], c.cur.eps_n);
    if (k >= 2) {
        c.cur.eps_p1 = simd::select(accept, c.cur.eps_p1 + x_new[1], c.cur.eps_p1);
    }
    if (k >= 3) {
        c.cur.eps_p2 = simd::select(accept, c.cur.eps_p2 + x_new[2], c.cur.eps_p2);
    }
    c.cur.gamma1 = simd::select(accept, c.cur.gamma1 + c.dgam1 * hl, c.cur.gamma1);
    c.cur.gamma2 = simd::select(accept, c.cur.gamma2 + c.dgam2 * hl, c.cur.gamma2);
    const T safe_hl = simd::max(hl, T(1.0e-300));
    for (int i = 0; i < 3; ++i) {
        c.x_rate[i] = simd::select(accept, x_new[i] / safe_hl, c.x_rate[i]);
    }
    // Accepted sub-increments keep the worst converged residual; a failed lane reports the
    // residual it stopped at, so the diagnostic says how far Eqs. 18-20 were from met.
    c.stats.residual = simd::select(accept || (c.failed && !full.converged),
                                    simd::max(c.stats.residual, full.residual), c.stats.residual);
    c.stats.subincrements += simd::select(accept, T(1.0), T(0.0));
    c.last_h = simd::select(accept, hl, c.last_h);
    c.t = simd::select(accept, t_end, c.t);
    c.h = adaptive ? simd::select(c.active, next_h, c.h) : c.h;
    c.active = c.active && ((T(1.0) - c.t) > 1.0e-12);
    c.count += simd::select(tried, T(1.0), T(0.0));
    const Mask limit = c.active && (c.count > static_cast<double>(s.max_subincrements));
    fail(limit, interface_failure::subincrement_limit);
    c.active = c.active && !limit;
    const Mask costly = c.active && (c.stats.model_substeps > s.max_model_substeps);
    fail(costly, interface_failure::work_limit);
    c.stats.residual = simd::select(costly, c.stats.model_substeps, c.stats.residual);
    c.active = c.active && !costly;
}

// The result of one evaluation: the new state into st (failed and separated lanes: unchanged, st
// must still hold the start state) and the statistics into stats.
template <class M, class T>
void interface_end(const InterfaceSettings& s, const Algorithm1Lane<T, M::n_state>& c,
                   InterfaceState<T, M::n_state>& st, InterfaceStats<T>& stats) {
    using Mask = simd::mask_t<T>;
    constexpr int NS = M::n_state;
    InterfaceState<T, NS> cur = c.cur;
    if (s.adaptive) {
        // A lane that chose its sub-increments records the last size for the next increment's
        // first try. A forced lane (equal sub-increments: the Eq. 37 lanes, a base held through
        // an increment, a frozen retry) records none, so the next choice starts again from the
        // paper's size and grows from there (at most 4x per sub-increment). Measured on the
        // coarse §6 scene and the FE shear box (docs/fem.md): starting each held increment
        // from the size of the last one, the error control took 1.3-1.8x fewer but larger
        // sub-increments that cost 1.7x the model substeps, at errors of the same size.
        const T used = c.last_h * c.total / s.max_subincrement;
        cur.last_subincrement =
            simd::select(c.run && !c.failed && (c.total > 0.0),
                         simd::select(c.forced, T(0.0), used), cur.last_subincrement);
    }
    stats = c.stats;
    // Failed and separated lanes keep their start state (a separated one carries no traction).
    stats.status = simd::select(c.failed, T(lane_status::failed), T(lane_status::ok));
    stats.open = simd::select(c.open && c.finite_in, T(1.0), T(0.0));
    stats.cause = simd::select(c.failed, c.cause, T(0.0));
    stats.band_clamped = simd::select(c.run && c.below, T(1.0), T(0.0));
    const Mask keep = c.failed || !c.run;
    st.y = select_state<T, NS>(keep, st.y, cur.y);
    st.eps_n = simd::select(keep, st.eps_n, cur.eps_n);
    st.eps_p1 = simd::select(keep, st.eps_p1, cur.eps_p1);
    st.eps_p2 = simd::select(keep, st.eps_p2, cur.eps_p2);
    st.gamma1 = simd::select(keep, st.gamma1, cur.gamma1);
    st.gamma2 = simd::select(keep, st.gamma2, cur.gamma2);
    st.last_subincrement = simd::select(keep, st.last_subincrement, cur.last_subincrement);
}

// The whole Algorithm 1 for one evaluation (one global increment) of an interface point.
// Writes the new state into st (failed lanes: unchanged) and the statistics into stats.
template <class M, class T>
void interface_update(const typename M::Params& mp, const InterfaceSettings& s,
                      InterfaceState<T, M::n_state>& st, const InterfaceInput<T>& in,
                      InterfaceStats<T>& stats) {
    auto c = interface_begin<M, T>(s, st, in);
    while (simd::any(c.active)) {
        interface_step<M, T>(mp, s, c);
    }
    interface_end<M, T>(s, c, st, stats);
}

} // namespace ifsim
