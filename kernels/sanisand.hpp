#pragma once
// Sanisand 2004 (Dafalias & Manzari 2004) with the interface roughness modification of
// Staubach, Machacek & Wichtmann (2022), Eqs. 33-35. Equations and choices: docs/models.md;
// rate equations in sanisand_rates.hpp, parameters in sanisand_params.hpp.
//
// State (flat, see model_api.hpp): [0..5] stress (mechanical sign), [6] e, [7..12] alpha
// (back-stress ratio), [13..18] z (fabric), [19..24] alpha_in (alpha at the last reversal).
//
// Explicit integration with per-lane substeps (modified Euler with error control, Sloan type):
// elastic inside the cone, the elastic-plastic transition found by a Pegasus search on f along
// the elastic path, elastic unloading when the loading numerator is <= 0, drift correction of
// alpha after every substep that ends on or outside the cone, alpha_in reset at load reversal.

#include <array>

#include "kernels/explicit_integration.hpp"
#include "kernels/model_api.hpp"
#include "kernels/sanisand_implicit.hpp"
#include "kernels/sanisand_params.hpp"
#include "kernels/sanisand_rates.hpp"

namespace ifsim {

struct Sanisand {
    static constexpr const char* name = "sanisand";
    static constexpr int n_state = sanisand::n_state;
    static constexpr int alpha_index = sanisand::alpha_index;
    static constexpr int z_index = sanisand::z_index;
    static constexpr int alpha_in_index = sanisand::alpha_in_index;
    // Integrated attempt by attempt (consistent_start, substep_attempt), so the engine could
    // refill finished SIMD lanes; it does not: with ~1 substep per update the refill's per-lane
    // load, prepare and finish of 25 state entries cost more than the idle lanes (refill/masked
    // 0.79 at 1e-4 increments, 0.40 at 1e-5; 1.24 at 1e-3, where points take many substeps;
    // docs/performance.md, SanisandPaths).
    static constexpr bool lane_refill = false;
    static constexpr bool pressure_floor = true;
    using Params = SanisandParams;
    template <class T>
    using State = StateVec<T, n_state>;

    // |f/p| within which a state counts as on the cone, and the accuracy of the crossing search.
    static constexpr double yield_tolerance = 1.0e-9;
    static constexpr int crossing_iterations = 60;
    // Largest move of the elastic-trial stress ratio in one loading substep, as a fraction of
    // the cone radius sqrt(2/3) m. The ratio component across n relaxes towards alpha at a rate
    // ~ (2G/p)/(sqrt(2/3) m) per unit strain; the error estimate does not see it on symmetric
    // paths, but the derivative of an increment does. With 1-2 substeps per increment that
    // derivative jumped between iterates of a mixed-control Newton (drained triaxial, 1e-4 steps:
    // 374 of 2000 increments failed at fraction 1.0, none and 2 iterations each at <= 0.7).
    static constexpr double cone_substep_fraction = 0.5;

    // Start state with alpha = alpha_in = dev(sigma)/p (on the cone's axis) and z = 0.
    static State<double> initial_state(const Sym<double>& stress, double e) {
        State<double> y{};
        set_stress(y, stress);
        y[state_index::void_ratio] = e;
        const double p = mean_pressure(stress);
        const Sym<double> r = voigt::scale(voigt::deviator(stress), p > 0.0 ? -1.0 / p : 0.0);
        set_sym_at(y, alpha_index, r);
        set_sym_at(y, alpha_in_index, r);
        return y;
    }

    template <class T>
    static simd::mask_t<T> admissible(const Params&, const IntegrationSettings& s,
                                      const State<T>& y) {
        return state_finite<T, n_state>(y) && (mean_pressure(stress_of(y)) >= s.min_pressure) &&
               (y[state_index::void_ratio] > 0.0);
    }

    // Relative difference of the Euler and Heun results: stress (floored at 1e-3 p_a so a
    // nearly liquefied state is not resolved below round-off), alpha (a ratio, O(1)), fabric, e.
    template <class T>
    static T local_error(const Params& P, const State<T>& yE, const State<T>& yH) {
        const T sn = simd::max(voigt::norm(stress_of(yH)), T(1.0e-3 * P.p_a));
        const T err_s = voigt::norm(voigt::sub(stress_of(yH), stress_of(yE))) / sn;
        const T err_a = voigt::norm(voigt::sub(sym_at(yH, alpha_index), sym_at(yE, alpha_index)));
        const Sym<T> zH = sym_at(yH, z_index);
        const T err_z = voigt::norm(voigt::sub(zH, sym_at(yE, z_index))) / (1.0 + voigt::norm(zH));
        const T eH = yH[state_index::void_ratio];
        const T err_e =
            simd::abs(eH - yE[state_index::void_ratio]) / simd::max(simd::abs(eH), T(1.0e-3));
        return simd::max(simd::max(err_s, err_a), simd::max(err_z, err_e));
    }

    // Low-pressure cut-off: the stress is scaled down to mean pressure p_min keeping its ratio r,
    // so alpha, alpha_in and z stay consistent with it (an isotropic cut-off would leave the state
    // outside the cone whenever ||alpha|| > sqrt(2/3) m); e follows the strain.
    template <class T>
    static State<T> cut_off(const Params&, const IntegrationSettings& s, const State<T>& y,
                            const Sym<T>& de_rest) {
        State<T> c = hold_at_floor(s, y);
        const T e = y[state_index::void_ratio];
        c[state_index::void_ratio] = simd::max(e + (1.0 + e) * voigt::trace(de_rest), T(1.0e-6));
        return c;
    }

    // The stress of y moved to mean pressure p_min along its own ratio (isotropic when p <= 0).
    template <class T>
    static State<T> hold_at_floor(const IntegrationSettings& s, const State<T>& y) {
        const Sym<T> sigma_c = voigt::scale(stress_of(y), T(-1.0));
        const T p = voigt::trace(sigma_c) * (1.0 / 3.0);
        const Sym<T> r = voigt::scale(voigt::deviator(sigma_c), 1.0 / simd::max(p, T(1.0e-300)));
        const Sym<T> ratio = voigt::select(p > 0.0, r, voigt::zero<T>());
        State<T> c = y;
        set_stress(c, voigt::scale(voigt::add(ratio, voigt::identity<T>()), T(-s.min_pressure)));
        return c;
    }

    // Modified Euler step over de: Euler state yE, Heun state yH and f/p at yH.
    template <class T>
    struct Trial {
        State<T> yE, yH;
        T f;
    };
    template <class T>
    static Trial<T> heun_step(const Params& P, const IntegrationSettings& s, const State<T>& y,
                              const Sym<T>& de, const simd::mask_t<T>& plastic_allowed) {
        Trial<T> tr;
        const State<T> k1 = sanisand::increment(P, s, y, de, plastic_allowed);
        for (int i = 0; i < n_state; ++i) {
            tr.yE[i] = y[i] + k1[i];
        }
        const State<T> k2 = sanisand::increment(P, s, tr.yE, de, plastic_allowed);
        for (int i = 0; i < n_state; ++i) {
            tr.yH[i] = y[i] + 0.5 * (k1[i] + k2[i]);
        }
        tr.f = sanisand::yield_ratio(P, s, tr.yH);
        return tr;
    }
    template <class T>
    static Trial<T> select_trial(const simd::mask_t<T>& m, const Trial<T>& a, const Trial<T>& b) {
        return {select_state<T, n_state>(m, a.yE, b.yE), select_state<T, n_state>(m, a.yH, b.yH),
                simd::select(m, a.f, b.f)};
    }

    // Elastic-plastic transition in the lanes `lanes`: the elastic path over de leaves the cone
    // (f(1) > 0). Finds beta with f(beta) = 0 by Pegasus, bracketed below by a point inside
    // (beta = 0 when the start is inside; found by halving when the start is on the cone and
    // unloads across it). Returns the trial at beta; `beta` gets the fraction per lane.
    template <class T>
    static Trial<T> elastic_crossing(const Params& P, const IntegrationSettings& s,
                                     const State<T>& y, const Sym<T>& de,
                                     const simd::mask_t<T>& lanes, const Trial<T>& at_one, T& beta,
                                     UpdateStats<T>& stats) {
        using Mask = simd::mask_t<T>;
        const Mask none(false);
        T x1(0.0);
        T f1 = sanisand::yield_ratio(P, s, y);
        Trial<T> best = at_one;
        beta = T(1.0);
        // Lower bracket for lanes starting on the cone: f < 0 just after the start.
        Mask pending = lanes && (f1 >= -yield_tolerance);
        T a(0.5);
        for (int k = 0; k < 40 && simd::any(pending); ++k) {
            const Trial<T> tr = heun_step(P, s, y, voigt::scale(de, a), none);
            stats.rate_evaluations += simd::select(pending, T(2.0), T(0.0));
            const Mask found = pending && (tr.f < 0.0);
            x1 = simd::select(found, a, x1);
            f1 = simd::select(found, tr.f, f1);
            // no inside point found yet: the smallest fraction tried is the fallback result
            best = select_trial(pending, tr, best);
            beta = simd::select(pending, a, beta);
            pending = pending && !found;
            a = simd::select(pending, 0.5 * a, a);
        }
        Mask open = lanes && !pending && (f1 < 0.0);
        T x2(1.0);
        T f2 = at_one.f;
        for (int k = 0; k < crossing_iterations && simd::any(open); ++k) {
            T x3 = x2 - f2 * (x2 - x1) / (f2 - f1);
            const Mask inside_bracket = (x3 > simd::min(x1, x2)) && (x3 < simd::max(x1, x2));
            x3 = simd::select(inside_bracket, x3, 0.5 * (x1 + x2));
            const Trial<T> tr = heun_step(P, s, y, voigt::scale(de, x3), none);
            stats.rate_evaluations += simd::select(open, T(2.0), T(0.0));
            const T f3 = tr.f;
            best = select_trial(open, tr, best);
            beta = simd::select(open, x3, beta);
            // Pegasus: keep the bracket; scale the retained end's value when it stays
            const Mask flip = open && (f3 * f2 < 0.0);
            const Mask keep = open && !flip;
            f1 = simd::select(flip, f2, simd::select(keep, f1 * f2 / (f2 + f3), f1));
            x1 = simd::select(flip, x2, x1);
            x2 = simd::select(open, x3, x2);
            f2 = simd::select(open, f3, f2);
            const Mask converged = (simd::abs(f3) <= yield_tolerance) ||
                                   (simd::abs(x2 - x1) <= 1.0e-15 * simd::max(x2, T(1.0e-300)));
            open = open && !converged;
        }
        return best;
    }

    // Before the first attempt: a start outside the cone (e.g. after the pressure floor
    // replaced the stress) is made consistent by moving alpha onto it. With substep_attempt,
    // what the engine's lane refill calls (engine/batched_update.hpp).
    template <class T>
    static void consistent_start(const Params& P, const IntegrationSettings& s, State<T>& y) {
        sanisand::remove_traces(y);
        sanisand::project_onto_cone(P, s, y, sanisand::yield_ratio(P, s, y) > 0.0);
    }

    // One substep attempt for every active lane (elastic, crossing or loading, with error
    // control); returns the lanes still active afterwards.
    template <class T>
    static simd::mask_t<T> substep_attempt(const Params& P, const IntegrationSettings& s,
                                           const simd::mask_t<T>& fixed, State<T>& y, T& t, T& dt,
                                           const Sym<T>& deps, UpdateStats<T>& stats,
                                           const simd::mask_t<T>& active) {
        using Mask = simd::mask_t<T>;
        const Sym<T> deps_c = voigt::scale(deps, T(-1.0));
        T dtl = simd::select(active, simd::min(dt, T(1.0) - t), T(0.0));

        // Loading test at the start of the substep: on the cone and the elastic trial
        // pointing out of it (positive numerator, as the notes advise).
        const sanisand::Point<T> q = sanisand::point(P, s, y);
        const Mask on_cone =
            active && (q.f >= -yield_tolerance) && (q.distance > sanisand::axis_tolerance);
        Mask loading(false);
        if (simd::any(on_cone)) {
            const sanisand::Plastic<T> k = sanisand::plastic(P, q, y);
            loading = on_cone && (sanisand::loading_numerator(q, k, deps_c) > 0.0);
            // New loading process: reset alpha_in when (alpha - alpha_in):n < 0.
            const Sym<T> a_in = sym_at(y, alpha_in_index);
            const Mask reversal = loading && (voigt::ddot(voigt::sub(q.alpha, a_in), q.n) < 0.0);
            set_sym_at(y, alpha_in_index, voigt::select(reversal, q.alpha, a_in));
        }

        // Loading substeps resolve the narrow cone (see cone_substep_fraction).
        {
            const T dr = 2.0 * q.G * voigt::norm(voigt::deviator(deps)) / q.p;
            const T cap =
                cone_substep_fraction * sanisand::sqrt_2_3 * P.m / simd::max(dr, T(1.0e-300));
            dtl = simd::select(loading && !fixed, simd::min(dtl, simd::max(cap, T(s.min_substep))),
                               dtl);
        }
        Sym<T> de = voigt::scale(deps, dtl);
        Trial<T> tr = heun_step(P, s, y, de, loading);
        stats.rate_evaluations += simd::select(active, T(2.0), T(0.0));

        // Elastic substeps that leave the cone end at the crossing point instead.
        const Mask crossing = active && !loading && (tr.f > yield_tolerance);
        if (simd::any(crossing)) {
            T beta(1.0);
            const Trial<T> cut = elastic_crossing(P, s, y, de, crossing, tr, beta, stats);
            tr = select_trial(crossing, cut, tr);
            dtl = simd::select(crossing, beta * dtl, dtl);
        }

        // A lane that starts at the pressure floor (liquefied, e.g. after a cut-off) keeps
        // integrating with p held at the floor, so its stress ratio, alpha and fabric can
        // evolve until dilation lifts p again; otherwise it would stay stuck at the floor.
        // Under volumetric extension a lane at the floor stays in the cut-off state instead:
        // with s fixed and p -> 0 the ratio would grow without bound.
        const T extension = voigt::trace(de) - 0.1 * voigt::norm(voigt::deviator(de));
        const Mask at_floor =
            active && (extension <= 0.0) && (mean_pressure(stress_of(y)) <= 2.0 * s.min_pressure);
        if (simd::any(at_floor)) {
            const Mask cE = at_floor && (mean_pressure(stress_of(tr.yE)) < s.min_pressure);
            const Mask cH = at_floor && (mean_pressure(stress_of(tr.yH)) < s.min_pressure);
            tr.yE = select_state<T, n_state>(cE, hold_at_floor(s, tr.yE), tr.yE);
            tr.yH = select_state<T, n_state>(cH, hold_at_floor(s, tr.yH), tr.yH);
            tr.f = sanisand::yield_ratio(P, s, tr.yH);
            stats.status = simd::select(
                cE || cH, simd::min(stats.status, T(lane_status::unreliable)), stats.status);
        }
        const Mask valid = admissible(P, s, tr.yE) && admissible(P, s, tr.yH);
        T err = local_error(P, tr.yE, tr.yH);
        err = simd::select(simd::isfinite(err), err, T(1.0e30));
        // As in integrate_explicit: an admissible substep of the smallest size is taken even
        // when it misses the tolerance (the capped h right after a reversal is not smooth), and
        // the lane is flagged unreliable rather than cut off.
        const Mask accurate = fixed || (err <= s.tolerance);
        const Mask forced = active && valid && !accurate && (dtl <= s.min_substep);
        const Mask accept = active && valid && (accurate || forced);
        stats.status =
            simd::select(forced, simd::min(stats.status, T(lane_status::unreliable)), stats.status);

        // Drift correction: plastic substeps, crossings and any overshoot end on f = 0.
        sanisand::remove_traces(tr.yH);
        sanisand::project_onto_cone(P, s, tr.yH, loading || crossing || (tr.f > 0.0));
        y = select_state<T, n_state>(accept, tr.yH, y);
        t = simd::select(accept, t + dtl, t);
        stats.substeps += simd::select(accept, T(1.0), T(0.0));
        stats.rejected += simd::select(active && !accept, T(1.0), T(0.0));

        // No admissible substep even at the smallest size: defined cut-off state.
        const Mask stuck = active && !accept && ((dtl <= s.min_substep) || fixed);
        if (simd::any(stuck)) {
            const State<T> yc = cut_off(P, s, y, voigt::scale(deps, T(1.0) - t));
            y = select_state<T, n_state>(stuck, yc, y);
            t = simd::select(stuck, T(1.0), t);
            stats.status = simd::select(stuck, simd::min(stats.status, T(lane_status::unreliable)),
                                        stats.status);
        }

        const T qf = 0.9 * simd::sqrt(s.tolerance / simd::max(err, T(1.0e-30)));
        const T grow = simd::min(T(s.max_step_growth), simd::max(T(s.min_step_shrink), qf));
        const T shrink =
            simd::select(valid, simd::max(T(s.min_step_shrink), simd::min(qf, T(0.5))), T(0.25));
        // after a crossing the next substep starts from the size planned before it
        T next = simd::select(accept, simd::select(crossing, dt, dtl * grow), dtl * shrink);
        next = simd::max(next, T(s.min_substep));
        dt = simd::select(active && !fixed, next, dt);
        return active && ((T(1.0) - t) > 1.0e-12);
    }

    template <class T>
    static void integrate(const Params& P, const IntegrationSettings& s,
                          const SubstepControl<T>& control, State<T>& y, const Sym<T>& deps,
                          UpdateStats<T>& stats) {
        if (s.backward_euler) {
            integrate_implicit(P, s, control, y, deps, stats);
            return;
        }
        using Mask = simd::mask_t<T>;
        const Mask fixed = control.fixed_substeps > 0.5;
        consistent_start(P, s, y);
        T t, dt;
        substep_begin<Sanisand, T>(s, control, y, deps, t, dt);
        Mask active = (T(1.0) - t) > 1.0e-12;
        for (int attempts = 0; simd::any(active) && attempts < s.max_substeps; ++attempts) {
            active = substep_attempt(P, s, fixed, y, t, dt, deps, stats, active);
        }
        // Runaway: not finished within max_substeps attempts.
        stats.status = simd::select(active, T(lane_status::failed), stats.status);
    }

    // Most halvings of an increment whose backward-Euler step did not converge (1..32 equal
    // steps) before the explicit scheme takes it.
    static constexpr int implicit_halvings = 5;

    // Backward-Euler integration: N equal steps, N = 1 (adaptive lanes; doubled while a step
    // fails) or the control's fixed number (perturbed lanes follow their base). Adaptive lanes
    // that find no converged implicit path are integrated by the explicit scheme. A fixed count
    // above 2^implicit_halvings is an explicit base's substep count: such lanes follow it
    // explicitly. A fixed lane whose implicit steps fail is reported failed, so a difference
    // quotient never mixes the two schemes.
    template <class T>
    static void integrate_implicit(const Params& P, const IntegrationSettings& s,
                                   const SubstepControl<T>& control, State<T>& y,
                                   const Sym<T>& deps, UpdateStats<T>& stats) {
        using Mask = simd::mask_t<T>;
        const Mask fixed = control.fixed_substeps > 0.5;
        const Mask explicit_fixed =
            fixed && (control.fixed_substeps > static_cast<double>(1 << implicit_halvings));
        consistent_start(P, s, y);
        const State<T> y0 = y;
        T pieces = simd::select(fixed, simd::max(control.fixed_substeps, T(1.0)), T(1.0));
        Mask todo = !explicit_fixed;
        Mask fixed_failed(false);
        for (int level = 0; level <= implicit_halvings && simd::any(todo); ++level) {
            State<T> yl = y0;
            Mask ok = todo;
            const Sym<T> de = voigt::scale(deps, 1.0 / pieces);
            for (int i = 0; simd::any(ok && (T(static_cast<double>(i)) < pieces)); ++i) {
                const Mask step = ok && (T(static_cast<double>(i)) < pieces);
                const sanisand::BeResult<T> r = sanisand::be_step(P, s, yl, de, step);
                stats.rate_evaluations += r.residual_evaluations;
                yl = select_state<T, n_state>(step && r.ok, r.y, yl);
                ok = ok && (!step || r.ok);
            }
            y = select_state<T, n_state>(todo && ok, yl, y);
            stats.substeps = simd::select(todo && ok, pieces, stats.substeps);
            stats.rejected += simd::select(todo && !ok, T(1.0), T(0.0));
            fixed_failed = fixed_failed || (todo && !ok && fixed);
            todo = todo && !ok && !fixed;
            pieces = simd::select(todo, 2.0 * pieces, pieces);
        }
        const Mask fallback = todo || explicit_fixed;
        if (simd::any(fallback)) {
            State<T> ye = y0;
            UpdateStats<T> es;
            IntegrationSettings explicit_settings = s;
            explicit_settings.backward_euler = false;
            const SubstepControl<T> ec{simd::select(explicit_fixed, control.fixed_substeps, T(0.0)),
                                       control.initial_substep};
            integrate(P, explicit_settings, ec, ye, deps, es);
            y = select_state<T, n_state>(fallback, ye, y);
            stats.substeps = simd::select(fallback, es.substeps, stats.substeps);
            stats.rejected += simd::select(fallback, es.rejected, T(0.0));
            stats.rate_evaluations += simd::select(fallback, es.rate_evaluations, T(0.0));
            stats.status = simd::select(fallback, simd::min(stats.status, es.status), stats.status);
        }
        y = select_state<T, n_state>(fixed_failed, y0, y);
        stats.status = simd::select(fixed_failed, T(lane_status::failed), stats.status);
    }

    // Continuum elastoplastic tangent at y for the loading branch selected by deps:
    // E - (E:R) (x) (df/dsigma):E / [Kp + (df/dsigma):E:R] when y is on the cone and deps loads,
    // else the hypoelastic E. Columns dsigma/deps_j with tensor shear components (the shear
    // column perturbs eps_ij and eps_ji together). The map is the same in both sign conventions.
    template <class T>
    static std::array<Sym<T>, 6> rate_stiffness(const Params& P, const IntegrationSettings& s,
                                                const State<T>& y, const Sym<T>& deps) {
        const sanisand::Point<T> q = sanisand::point(P, s, y);
        const sanisand::Plastic<T> k = sanisand::plastic(P, q, y);
        const Sym<T> deps_c = voigt::scale(deps, T(-1.0));
        const simd::mask_t<T> loading = (q.f >= -yield_tolerance) &&
                                        (q.distance > sanisand::axis_tolerance) &&
                                        (sanisand::loading_numerator(q, k, deps_c) > 0.0);
        const T inv_den = simd::select(loading, 1.0 / sanisand::loading_denominator(q, k), T(0.0));
        std::array<Sym<T>, 6> cols;
        for (int j = 0; j < 6; ++j) {
            Sym<T> unit = voigt::zero<T>();
            unit[j] = T(1.0);
            const T L = sanisand::loading_numerator(q, k, unit) * inv_den;
            const Sym<T> dev = voigt::deviator(unit);
            const T tr = voigt::trace(unit);
            for (int i = 0; i < 6; ++i) {
                const T elastic = 2.0 * q.G * dev[i] + (i < 3 ? q.K * tr : T(0.0));
                const T flow = 2.0 * q.G * k.Rdev[i] + (i < 3 ? q.K * k.D : T(0.0));
                cols[j][i] = elastic - L * flow;
            }
        }
        return cols;
    }
};

} // namespace ifsim
