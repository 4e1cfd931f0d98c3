#pragma once
// Algorithm 1 of the paper (§3.5): a continuum model M used as interface model. The shear
// strain increment (Eq. 25) is split into sub-increments; inside each, a Newton iteration on the
// interface normal strains (Eqs. 21-23) drives the interface normal stresses to their targets
// (Eqs. 18-20: sigma_N = t_N and, for the novel formulation, sigma_p1/p2 = extrapolated
// continuum stress), with the shear stresses of the last converged state carried along
// (Eqs. 24, 27). The model is called unchanged through material_update(), so any constitutive
// model of the material engine plugs in.
//
// Per lane: own number of sub-increments, own Newton convergence (masks); a lane that fails
// (Newton not converged, model failure, band collapse) keeps its start state and reports
// status failed so the caller can cut the increment.

#include <array>

#include "kernels/interface_settings.hpp"
#include "kernels/material_update.hpp"
#include "kernels/small_solve.hpp"

namespace ifsim {

// Number of normal-strain unknowns: Stutz: eps_N; novel 2D: eps_N, eps_p1; novel 3D: all three.
inline int interface_unknowns(const InterfaceSettings& s) {
    return s.formulation == InterfaceFormulation::stutz ? 1 : (s.ndim == 2 ? 2 : 3);
}

template <class T, int NS>
struct SubincrementResult {
    StateVec<T, NS> y;
    std::array<T, 3> x{T(0.0), T(0.0), T(0.0)}; // converged normal strain increments
    simd::mask_t<T> converged{};
    simd::mask_t<T> model_failed{};
    T residual = T(0.0);
};

// The strain increment of one Newton iterate: normal parts from x, shear from the
// sub-increment of shear strain (tensor components gamma/2), Eq. 27.
template <class T>
Sym<T> interface_strain_increment(int k, const std::array<T, 3>& x, const T& dgam1,
                                  const T& dgam2) {
    return {x[0], k >= 2 ? x[1] : T(0.0), k >= 3 ? x[2] : T(0.0), 0.5 * dgam1, 0.5 * dgam2, T(0.0)};
}

// One sub-increment: Newton on the normal strains from y0 (Algorithm 1 lines 3-10).
template <class M, class T>
SubincrementResult<T, M::n_state>
solve_subincrement(const typename M::Params& mp, const InterfaceSettings& s,
                   const StateVec<T, M::n_state>& y0, const std::array<T, 3>& x_guess,
                   const T& dgam1, const T& dgam2, const std::array<T, 3>& target,
                   const simd::mask_t<T>& active, InterfaceStats<T>& stats) {
    using Mask = simd::mask_t<T>;
    constexpr int NS = M::n_state;
    const int k = interface_unknowns(s);
    T ref = target[0] * target[0];
    for (int c = 1; c < k; ++c) {
        ref += target[c] * target[c];
    }
    ref = simd::max(simd::sqrt(ref), T(1.0e-3));

    SubincrementResult<T, NS> out;
    out.y = y0;
    out.converged = !active;
    out.model_failed = Mask(false);
    std::array<T, 3> x = x_guess;
    const SubstepControl<T> adaptive_ctl{};
    Mask failed(false); // lanes whose model update or Newton matrix failed
    // Lanes below the tolerance that still take their polishing corrections.
    T polish_left = T(static_cast<double>(s.polish_iterations));
    Mask met(false);
    for (int it = 0; it <= s.max_newton_iterations + s.polish_iterations; ++it) {
        const Mask working = active && !out.converged && !failed;
        if (simd::none(working)) {
            break;
        }
        const Sym<T> de = interface_strain_increment(k, x, dgam1, dgam2);
        StateVec<T, NS> yt = y0;
        UpdateStats<T> ms;
        material_update<M, T>(mp, s.model, adaptive_ctl, yt, de, ms);
        stats.evaluations += simd::select(working, T(1.0), T(0.0));
        stats.model_substeps += simd::select(working, ms.substeps, T(0.0));

        std::array<T, 3> res{T(0.0), T(0.0), T(0.0)};
        T r2 = T(0.0);
        for (int c = 0; c < k; ++c) {
            res[c] = yt[c] - target[c];
            r2 += res[c] * res[c];
        }
        const T r = simd::sqrt(r2) / ref;
        const Mask model_ok = ms.status > -0.5;
        met = met || (working && model_ok && (r < s.tolerance));
        const Mask now = working && model_ok && met && (polish_left < 0.5);
        out.y = select_state<T, NS>(now, yt, out.y);
        for (int c = 0; c < 3; ++c) {
            out.x[c] = simd::select(now, x[c], out.x[c]);
        }
        out.residual = simd::select(now, r, out.residual);
        out.converged = out.converged || now;
        failed = failed || (working && !model_ok);
        out.model_failed = out.model_failed || (working && !model_ok);
        const Mask iterate = working && !now && model_ok;
        polish_left = simd::select(iterate && met, polish_left - 1.0, polish_left);
        if (simd::none(iterate) || it == s.max_newton_iterations + s.polish_iterations) {
            // Lanes that met the tolerance but ran out of iterations keep their last iterate.
            const Mask take = iterate && met;
            out.y = select_state<T, NS>(take, yt, out.y);
            for (int c = 0; c < 3; ++c) {
                out.x[c] = simd::select(take, x[c], out.x[c]);
            }
            out.converged = out.converged || take;
            out.residual = simd::select(iterate, r, out.residual);
            break;
        }

        // Jacobian d sigma_normal / d eps_normal (Eq. 22).
        std::array<std::array<T, 3>, 3> J{};
        if (s.newton_jacobian == NewtonJacobian::rate) {
            const auto cols = M::template rate_stiffness<T>(mp, s.model, y0, de);
            for (int rr = 0; rr < k; ++rr) {
                for (int c = 0; c < k; ++c) {
                    J[rr][c] = cols[c][rr];
                }
            }
        } else {
            // Same number of equal substeps as the base, so the quotient sees no step noise.
            SubstepControl<T> fixed;
            fixed.fixed_substeps = simd::max(ms.substeps, T(1.0));
            const T delta = s.newton_perturbation * simd::max(voigt::norm(de), T(1.0e-9));
            StateVec<T, NS> yb = y0;
            UpdateStats<T> bs;
            material_update<M, T>(mp, s.model, fixed, yb, de, bs);
            stats.evaluations += simd::select(iterate, T(1.0), T(0.0));
            for (int c = 0; c < k; ++c) {
                Sym<T> dp = de;
                dp[c] += delta;
                StateVec<T, NS> yp = y0;
                UpdateStats<T> ps;
                material_update<M, T>(mp, s.model, fixed, yp, dp, ps);
                stats.evaluations += simd::select(iterate, T(1.0), T(0.0));
                for (int rr = 0; rr < k; ++rr) {
                    J[rr][c] = (yp[rr] - yb[rr]) / delta;
                }
            }
        }
        const SmallSolve<T> sol = small_solve<T>(k, J, res);
        failed = failed || (iterate && !sol.solved);
        const Mask step = iterate && sol.solved;
        for (int c = 0; c < k; ++c) {
            x[c] = simd::select(step, x[c] - sol.x[c], x[c]);
        }
        stats.newton_iterations += simd::select(step, T(1.0), T(0.0));
    }
    return out;
}

// The whole Algorithm 1 for one evaluation (one global increment) of an interface point.
// Writes the new state into st (failed lanes: unchanged) and the statistics into stats.
template <class M, class T>
void interface_update(const typename M::Params& mp, const InterfaceSettings& s,
                      InterfaceState<T, M::n_state>& st, const InterfaceInput<T>& in,
                      InterfaceStats<T>& stats) {
    using Mask = simd::mask_t<T>;
    constexpr int NS = M::n_state;
    const int k = interface_unknowns(s);
    stats = InterfaceStats<T>{};

    const Mask finite_in = simd::isfinite(in.t_N) && simd::isfinite(in.dg1) &&
                           simd::isfinite(in.dg2) && simd::isfinite(in.s_p1) &&
                           simd::isfinite(in.s_p2) && state_finite<T, NS>(st.y);
    // Eq. 26: band thickness following the interface normal strain.
    const T d_s_floor = T(s.min_band_fraction * s.shear_band_thickness);
    const T d_s_eq26 = s.shear_band_thickness * (1.0 + st.eps_n);
    const Mask below = !(d_s_eq26 > d_s_floor);
    const Mask band_ok = s.clamp_band ? Mask(true) : !below;
    const T d_s = simd::select(below, d_s_floor, d_s_eq26);
    // Contact open (no compression to carry): the point keeps its state and transmits nothing.
    // The threshold sits above the models' pressure floor so that an almost open contact is
    // not driven into the floor by the in-plane stresses (K0 < 1 lowers p below t_N).
    const Mask open = in.t_N > -s.open_threshold;
    const Mask run = finite_in && band_ok && !open;

    // Eq. 25: tan(delta gamma) = delta g_T / d_s.
    const T safe_ds = simd::select(band_ok, d_s, T(s.shear_band_thickness));
    const T dgam1 = simd::select(run, simd::atan(in.dg1 / safe_ds), T(0.0));
    const T dgam2 =
        (s.ndim == 2) ? T(0.0) : simd::select(run, simd::atan(in.dg2 / safe_ds), T(0.0));
    const T total = simd::max(simd::abs(dgam1), simd::abs(dgam2));

    // Targets of Eqs. 18-20 are met at the end of the increment; the sub-increments in between
    // follow a straight path from the start values (sigma_N, sigma_p1, sigma_p2 of the converged
    // state), so a change of t_N or of the continuum stress is spread over the sub-increments
    // instead of being forced into the first one.
    const std::array<T, 3> target_end = {in.t_N, in.s_p1, in.s_p2};
    const std::array<T, 3> target_start = {st.y[0], st.y[1], st.y[2]};
    auto target_at = [&](const T& frac) {
        std::array<T, 3> tg;
        for (int c = 0; c < 3; ++c) {
            tg[c] = target_start[c] + (target_end[c] - target_start[c]) * frac;
        }
        return tg;
    };
    // Sub-increments needed for the change of the normal targets: at most max_normal_change of
    // the stress per sub-increment (a change of t_N without shear would otherwise be one step).
    T dtarget = T(0.0);
    T tnorm = T(0.0);
    for (int c = 0; c < k; ++c) {
        dtarget = simd::max(dtarget, simd::abs(target_end[c] - target_start[c]));
        tnorm += target_end[c] * target_end[c];
    }
    tnorm = simd::max(simd::sqrt(tnorm), T(1.0));
    const T n_normal =
        simd::select(run, simd::ceil(dtarget / (s.max_normal_change * tnorm)), T(1.0));

    // Sub-increment size as a fraction of the increment. Fixed: n_sub = ceil(total / max).
    const Mask forced = in.forced_subincrements > 0.5;
    const T n_fixed = simd::select(
        forced, in.forced_subincrements,
        simd::max(simd::max(simd::ceil(total / s.max_subincrement), n_normal), T(1.0)));
    T h = 1.0 / n_fixed;
    const bool adaptive = s.adaptive && !simd::all(forced);
    if (adaptive) {
        // Start from the last accepted size (in units of max_subincrement) or the paper's size.
        const T last = simd::select(st.last_subincrement > 0.0, st.last_subincrement, T(1.0));
        const T frac = last * s.max_subincrement / simd::max(total, T(1.0e-300));
        const T h0 = simd::min(T(1.0), simd::select(total > 0.0, frac, T(1.0)));
        h = simd::select(forced, h, simd::min(h0, 1.0 / simd::max(n_normal, T(1.0))));
    }

    InterfaceState<T, NS> cur = st;
    T t = T(0.0);
    T last_h = h;
    std::array<T, 3> x_rate{T(0.0), T(0.0), T(0.0)}; // normal strain increment per unit fraction
    Mask active = run;
    Mask failed = !finite_in || !band_ok;
    T cause = simd::select(!finite_in, T(interface_failure::non_finite_input),
                           simd::select(!band_ok, T(interface_failure::band_collapse), T(0.0)));
    // Records the first reason a lane fails.
    auto fail = [&](const Mask& m, double code) {
        cause = simd::select(m && !failed, T(code), cause);
        failed = failed || m;
    };
    long count = 0;
    while (simd::any(active)) {
        const T hl = simd::select(active, simd::min(h, T(1.0) - t), T(0.0));
        std::array<T, 3> guess;
        for (int c = 0; c < 3; ++c) {
            guess[c] = x_rate[c] * hl;
        }
        const T t_end = simd::select(hl >= (T(1.0) - t), T(1.0), t + hl);
        const auto full = solve_subincrement<M, T>(mp, s, cur.y, guess, dgam1 * hl, dgam2 * hl,
                                                   target_at(t_end), active, stats);
        Mask accept = active && full.converged;
        StateVec<T, NS> y_new = full.y;
        std::array<T, 3> x_new = full.x;
        T next_h = h;
        if (adaptive) {
            // Step doubling: two half sub-increments against the full one.
            const T hh = 0.5 * hl;
            std::array<T, 3> g2;
            for (int c = 0; c < 3; ++c) {
                g2[c] = 0.5 * full.x[c];
            }
            const auto a = solve_subincrement<M, T>(mp, s, cur.y, g2, dgam1 * hh, dgam2 * hh,
                                                    target_at(t + hh), accept && !forced, stats);
            const auto b = solve_subincrement<M, T>(mp, s, a.y, a.x, dgam1 * hh, dgam2 * hh,
                                                    target_at(t_end), accept && a.converged, stats);
            const Mask both = accept && a.converged && b.converged;
            // Error of the shear stresses (the normal ones are pinned by Eqs. 18-20).
            const T dt1 = b.y[3] - full.y[3];
            const T dt2 = b.y[4] - full.y[4];
            const T scale = simd::max(voigt::norm(stress_of(b.y)), T(1.0e-3));
            const T err = simd::sqrt(dt1 * dt1 + dt2 * dt2) / scale;
            const Mask accurate = (err <= s.adaptive_tolerance) || forced;
            const T q = 0.9 * simd::sqrt(s.adaptive_tolerance / simd::max(err, T(1.0e-30)));
            // Forced lanes (uniform sub-increments) take the full sub-increment as it is.
            accept = simd::select_mask(forced, accept, both && accurate);
            y_new = select_state<T, NS>(forced, full.y, b.y);
            for (int c = 0; c < 3; ++c) {
                x_new[c] = simd::select(forced, full.x[c], a.x[c] + b.x[c]);
            }
            const T grow = simd::min(T(4.0), simd::max(T(0.2), q));
            const T shrink = simd::select(both, simd::max(T(0.2), simd::min(q, T(0.5))), T(0.25));
            next_h = simd::select(forced, h, simd::select(accept, hl * grow, hl * shrink));
            // A sub-increment that cannot be made small enough ends the lane as failed.
            const Mask too_small = active && !accept && ((hl * total < 1.0e-12) || forced);
            fail(too_small && full.model_failed, interface_failure::model);
            fail(too_small, interface_failure::newton);
            active = active && !too_small;
        } else {
            fail(active && full.model_failed, interface_failure::model);
            fail(active && !full.converged, interface_failure::newton);
            active = active && full.converged;
        }
        // Eq. 26 within the increment: a sub-increment that takes d_s below its floor ends the
        // lane (band collapse) unless the floor is to be held.
        if (!s.clamp_band) {
            const Mask collapses =
                accept && !(s.shear_band_thickness * (1.0 + cur.eps_n + x_new[0]) > d_s_floor);
            fail(collapses, interface_failure::band_collapse);
            accept = accept && !collapses;
            active = active && !collapses;
        }
        // Algorithm 1 lines 11-13: save strain, state and stress of the converged sub-increment.
        y_new[5] = T(0.0); // Eq. 17: no t1-t2 shear in the interface
        cur.y = select_state<T, NS>(accept, y_new, cur.y);
        cur.eps_n = simd::select(accept, cur.eps_n + x_new[0], cur.eps_n);
        if (k >= 2) {
            cur.eps_p1 = simd::select(accept, cur.eps_p1 + x_new[1], cur.eps_p1);
        }
        if (k >= 3) {
            cur.eps_p2 = simd::select(accept, cur.eps_p2 + x_new[2], cur.eps_p2);
        }
        cur.gamma1 = simd::select(accept, cur.gamma1 + dgam1 * hl, cur.gamma1);
        cur.gamma2 = simd::select(accept, cur.gamma2 + dgam2 * hl, cur.gamma2);
        const T safe_hl = simd::max(hl, T(1.0e-300));
        for (int c = 0; c < 3; ++c) {
            x_rate[c] = simd::select(accept, x_new[c] / safe_hl, x_rate[c]);
        }
        // Accepted sub-increments keep the worst converged residual; a failed lane reports the
        // residual it stopped at, so the diagnostic says how far Eqs. 18-20 were from met.
        stats.residual = simd::select(accept || (failed && !full.converged),
                                      simd::max(stats.residual, full.residual), stats.residual);
        stats.subincrements += simd::select(accept, T(1.0), T(0.0));
        last_h = simd::select(accept, hl, last_h);
        t = simd::select(accept, t_end, t);
        h = adaptive ? simd::select(active, next_h, h) : h;
        active = active && ((T(1.0) - t) > 1.0e-12);
        if (++count > s.max_subincrements) {
            fail(active, interface_failure::subincrement_limit);
            break;
        }
    }
    if (adaptive) {
        const T used = last_h * total / s.max_subincrement;
        cur.last_subincrement =
            simd::select(run && !failed && (total > 0.0) && !forced, used, cur.last_subincrement);
    }
    // Failed lanes keep their start state; open lanes keep theirs and carry no traction.
    stats.status = simd::select(failed, T(lane_status::failed), T(lane_status::ok));
    stats.open = simd::select(open && finite_in, T(1.0), T(0.0));
    stats.cause = simd::select(failed, cause, T(0.0));
    stats.band_clamped = simd::select(run && below, T(1.0), T(0.0));
    const Mask keep = failed || !run;
    st.y = select_state<T, NS>(keep, st.y, cur.y);
    st.eps_n = simd::select(keep, st.eps_n, cur.eps_n);
    st.eps_p1 = simd::select(keep, st.eps_p1, cur.eps_p1);
    st.eps_p2 = simd::select(keep, st.eps_p2, cur.eps_p2);
    st.gamma1 = simd::select(keep, st.gamma1, cur.gamma1);
    st.gamma2 = simd::select(keep, st.gamma2, cur.gamma2);
    st.last_subincrement = simd::select(keep, st.last_subincrement, cur.last_subincrement);
}

} // namespace ifsim
