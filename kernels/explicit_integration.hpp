#pragma once
// Explicit integration of a rate-type constitutive model over one strain increment, per lane,
// with local error control (Sloan et al. 2001 style substepping):
//  - heun:  modified Euler 1(2); the error estimate is that of the Euler result, the Heun
//           result is kept. 2 rate evaluations per substep, controller exponent 1/2.
//  - rkf23: Runge-Kutta-Fehlberg 2(3) (the scheme of the public hypoplastic UMATs; Fellin &
//           Ostermann 2002): stages k1 = f(y), k2 = f(y + k1), k3 = f(y + (k1 + k2)/4);
//           y2 = y + (k1 + k2)/2, y3 = y + (k1 + k2 + 4 k3)/6. The error estimate is that of
//           the second-order y2, the third-order y3 is kept. 3 evaluations, exponent 1/3.
//
// Pseudo-time t in [0, 1] runs over the increment; a substep of size dt applies the strain
// dt * deps. Each lane keeps its own t and dt, so lanes of a SIMD batch take different substeps;
// finished lanes stay masked until the slowest lane of the batch is done (or, in the engine's
// refill loop, take the next point at once).
//
// A model whose internal state evolves with itself and the strain only (declares
// `internal_index`: hypoplasticity's intergranular strain h) has it integrated on its own inside
// each substep (split_internal): h is a known function of the pseudo-time there, integrated to
// the tolerance by a cheap RKF23 of its own rate, and the stress stages take h at their times
// (c = 1 for the second stage, 1/2 for the third). The substep's error estimate then covers
// stress and void ratio; h's own accuracy is that of its sub-integration. The transition of h
// after a reversal is then resolved without re-evaluating the stress rate at every small step.
//
// A model that declares `substep_index` carries the size of its next substep between
// increments in that state entry, as a strain norm (0 = none yet): an update starts from the
// size its point ended the last one with instead of the whole increment.
//
// The model M provides (all templates over T, no allocation, no throwing):
//   State euler_increment(p, s, y, de)  increment of the state for the strain increment de
//   T     local_error(p, s, yLow, yHigh) relative error between a lower- and higher-order result
//   mask  admissible(p, s, y)           state may be used (finite, pressure above the floor)
//   void  correct(p, y)                 projection after an accepted substep (drift, |h| <= R)
//   State cut_off(p, s, y, de_rest)     defined end state when no substep is admissible

#include <cmath>

#include "kernels/model_api.hpp"

namespace ifsim {

// Per lane: fixed_substeps = 0 integrates adaptively with error control; n > 0 takes exactly n
// equal substeps without error control (perturbed evaluations that must follow the same
// discretisation as their base, so a finite difference sees no step-selection noise).
template <class T>
struct SubstepControl {
    T fixed_substeps = T(0.0);
    T initial_substep = T(1.0);
};

template <class M>
concept CarriesSubstep = requires {
    M::substep_index;
};

// Largest growth of the carried substep over the last accepted one: with a vanishing error
// estimate the controller's ratio is unbounded, and a carried size far above what was tried
// would only be rejected in the next increment.
inline constexpr double max_carried_growth = 10.0;

// First substep of an adaptive lane as a fraction of the increment: the carried substep strain
// over the increment's norm when the model carries one, else the control's initial size.
template <class M, class T>
T first_substep(const IntegrationSettings& s, const SubstepControl<T>& control,
                const StateVec<T, M::n_state>& y, const Sym<T>& deps) {
    if constexpr (CarriesSubstep<M>) {
        if (!s.carry_substep) {
            return control.initial_substep;
        }
        const T carried = y[M::substep_index];
        const T dn = voigt::norm(deps);
        const T from_carried = carried / simd::max(dn, T(1.0e-300));
        return simd::select((carried > 0.0) && (dn > 0.0), from_carried, control.initial_substep);
    } else {
        (void)s;
        (void)y;
        (void)deps;
        return control.initial_substep;
    }
}

// End of an adaptive lane's increment: store the controller's estimate as a strain norm.
template <class M, class T>
void carry_substep(StateVec<T, M::n_state>& y, const Sym<T>& deps, const T& ideal_substep,
                   const simd::mask_t<T>& fixed) {
    if constexpr (CarriesSubstep<M>) {
        const T size = ideal_substep * voigt::norm(deps);
        const simd::mask_t<T> keep = fixed || !(size > 0.0);
        y[M::substep_index] = simd::select(keep, y[M::substep_index], size);
    } else {
        (void)y;
        (void)deps;
        (void)ideal_substep;
        (void)fixed;
    }
}

// Start of an increment: pseudo-time 0 and the first substep size.
template <class M, class T>
void substep_begin(const IntegrationSettings& s, const SubstepControl<T>& control,
                   const StateVec<T, M::n_state>& y, const Sym<T>& deps, T& t, T& dt) {
    const simd::mask_t<T> fixed = control.fixed_substeps > 0.5;
    t = T(0.0);
    const T first = first_substep<M, T>(s, control, y, deps);
    dt = simd::select(fixed, 1.0 / simd::max(control.fixed_substeps, T(1.0)),
                      simd::min(simd::max(first, T(s.min_substep)), T(1.0)));
}

template <class M>
concept SplitsInternal = requires {
    M::internal_index;
};

template <class M>
bool split_internal(const typename M::Params& p, const IntegrationSettings& s) {
    if constexpr (SplitsInternal<M>) {
        return s.split_internal && M::has_internal(p);
    } else {
        (void)p;
        (void)s;
        return false;
    }
}

namespace detail {

// Controller ratio (tolerance / error)^(1 / (order of the estimate)) with a safety factor.
template <class T>
T controller_ratio(IntegrationScheme scheme, double tolerance, const T& err) {
    const T ratio = tolerance / simd::max(err, T(1.0e-30));
    return 0.9 * (scheme == IntegrationScheme::heun ? simd::sqrt(ratio) : simd::cbrt(ratio));
}

// Smallest step of the internal state's sub-integration, as a fraction of its interval; a step
// of this size is taken whatever its error (h's rate is not smooth where h = 0).
inline constexpr double min_internal_step = 1.0e-6;
inline constexpr int max_internal_attempts = 100000;

// The decoupled internal state h integrated over the strain de, adaptively with RKF23 on its
// own rate (error relative to M::internal_scale, tolerance s.tolerance). Returns h at the end;
// h_mid gets h at the middle of the interval, where every lane's steps are cut. (Taking it
// from the stage value of one step over the whole interval is cheaper in steps, but the
// second-order value costs the stress its accuracy: on a cyclic path the global error grew to
// 10 tol; a cubic Hermite value restores it but is slower than the cut, measured.)
// Lanes in `fixed` (equal substeps of the stress, for finite differences) take equal steps of h
// too, with no error control and no cut at a kink, so their result is a smooth function of de:
// steps of scale * tolerance^(1/3) (RKF23's local error ~ (step/scale)^3), far below the
// stability limit ~2 scale of h's relaxation (tests/kernels/test_integration.cpp).
template <class M, class T>
Sym<T> integrate_internal(const typename M::Params& p, const IntegrationSettings& s, Sym<T> h,
                          const Sym<T>& de, Sym<T>& h_mid, const simd::mask_t<T>& fixed) {
    using Mask = simd::mask_t<T>;
    const double inv_scale = 1.0 / M::internal_scale(p);
    const double equal_step = std::cbrt(s.tolerance); // RKF23's local error ~ (step/scale)^3
    const T equal_steps = simd::max(
        T(1.0), simd::ceil(voigt::norm(de) * (0.5 * inv_scale / equal_step) * (1.0 - 1.0e-12)));
    T t(0.0);
    T dt = simd::select(fixed, 0.5 / equal_steps, T(1.0));
    Mask run = Mask(true);
    h_mid = h;
    for (int k = 0; k < max_internal_attempts && simd::any(run); ++k) {
        const T room = T(1.0) - t;
        // the last attempt takes the rest of the interval, whatever its error
        const bool last = k + 1 == max_internal_attempts;
        const T to_mid = simd::select(t < 0.5, 0.5 - t, room);
        T dtl = simd::min(dt, to_mid);
        // A switch of the rate's branch ahead (a kink) ends the step: the part before it is
        // smooth (for h linear, so integrated exactly), the part after it too.
        const T kink = M::internal_switch(p, h, voigt::scale(de, room)) * room;
        dtl = simd::select(!fixed && (kink > 1.0e-9) && (kink < dtl), simd::min(kink, to_mid), dtl);
        // equal steps: the last one before the middle or the end takes the rounding
        dtl = simd::select(fixed && (to_mid - dtl < 1.0e-9), to_mid, dtl);
        dtl = simd::select(run, last ? room : dtl, T(0.0));
        const Sym<T> d = voigt::scale(de, dtl);
        const Sym<T> k1 = M::internal_increment(p, h, d);
        const Sym<T> k2 = M::internal_increment(p, voigt::add(h, k1), d);
        const Sym<T> k12 = voigt::add(k1, k2);
        const Sym<T> hQ = voigt::axpy(h, T(0.25), k12);
        const Sym<T> k3 = M::internal_increment(p, hQ, d);
        const Sym<T> low = voigt::axpy(h, T(0.5), k12);
        Sym<T> high = voigt::axpy(h, T(1.0 / 6.0), voigt::axpy(k12, T(4.0), k3));
        T err = voigt::norm(voigt::sub(high, low)) * inv_scale;
        err = simd::select(simd::isfinite(err), err, T(1.0e30));
        const Mask accept =
            run && (fixed || (err <= s.tolerance) || (dtl <= min_internal_step) || Mask(last));
        M::correct_internal(p, high);
        const Mask reaches_mid = accept && (t < 0.5) && (t + dtl >= 0.5 - 1.0e-12);
        h_mid = voigt::select(reaches_mid, high, h_mid);
        h = voigt::select(accept, high, h);
        t = simd::select(accept, simd::select(reaches_mid, T(0.5), t + dtl), t);
        const T q = controller_ratio(IntegrationScheme::rkf23, s.tolerance, err);
        const T next = simd::select(accept, dtl * simd::min(T(4.0), simd::max(T(0.2), q)),
                                    dtl * simd::max(T(0.1), simd::min(q, T(0.5))));
        dt = simd::select(run && !fixed, simd::max(next, T(min_internal_step)), dt);
        run = run && ((T(1.0) - t) > 1.0e-12);
    }
    return h;
}

// One substep of the chosen scheme from y over the strain de: the kept (higher-order) result,
// the lower-order one for the error estimate, and whether every evaluated stage was admissible.
template <class M, class T>
struct SchemeStep {
    StateVec<T, M::n_state> kept;
    StateVec<T, M::n_state> low;
    simd::mask_t<T> valid;
};

// With split = true the internal state of every stage and result is replaced by its own
// sub-integration at the stage's time (c = 1 for yE, 1/2 for the RKF23 stage yQ).
template <class M, class T>
SchemeStep<M, T> scheme_step(const typename M::Params& p, const IntegrationSettings& s,
                             const StateVec<T, M::n_state>& y, const Sym<T>& de, bool split,
                             const simd::mask_t<T>& fixed) {
    constexpr int N = M::n_state;
    SchemeStep<M, T> r;
    Sym<T> h_mid, h_end;
    auto set_internal = [&](StateVec<T, N>& v, const Sym<T>& h) {
        if constexpr (SplitsInternal<M>) {
            if (split) {
                set_sym_at(v, M::internal_index, h);
            }
        }
    };
    if constexpr (SplitsInternal<M>) {
        if (split) {
            h_end = integrate_internal<M, T>(p, s, sym_at(y, M::internal_index), de, h_mid, fixed);
        }
    }
    const StateVec<T, N> k1 = M::euler_increment(p, s, y, de);
    StateVec<T, N> yE;
    for (int i = 0; i < N; ++i) {
        yE[i] = y[i] + k1[i];
    }
    set_internal(yE, h_end);
    const StateVec<T, N> k2 = M::euler_increment(p, s, yE, de);
    if (s.scheme == IntegrationScheme::heun) {
        for (int i = 0; i < N; ++i) {
            r.kept[i] = y[i] + 0.5 * (k1[i] + k2[i]);
        }
        set_internal(r.kept, h_end);
        r.low = yE;
        r.valid = M::admissible(p, s, yE) && M::admissible(p, s, r.kept);
        return r;
    }
    StateVec<T, N> yQ; // stage state at a quarter of the summed slopes (c = 1/2)
    for (int i = 0; i < N; ++i) {
        yQ[i] = y[i] + 0.25 * (k1[i] + k2[i]);
    }
    set_internal(yQ, h_mid);
    const StateVec<T, N> k3 = M::euler_increment(p, s, yQ, de);
    for (int i = 0; i < N; ++i) {
        r.low[i] = y[i] + 0.5 * (k1[i] + k2[i]);
        r.kept[i] = y[i] + (k1[i] + k2[i] + 4.0 * k3[i]) * (1.0 / 6.0);
    }
    set_internal(r.low, h_end);
    set_internal(r.kept, h_end);
    r.valid = M::admissible(p, s, yE) && M::admissible(p, s, yQ) && M::admissible(p, s, r.kept);
    return r;
}

inline int scheme_evaluations(IntegrationScheme scheme) {
    return scheme == IntegrationScheme::heun ? 2 : 3;
}

} // namespace detail

// One substep attempt for every active lane: accepted lanes advance t and y, rejected ones
// shrink dt; a lane that cannot take even the smallest admissible substep ends in the model's
// cut-off state. Returns the lanes still active afterwards.
template <class M, class T>
simd::mask_t<T> substep_attempt(const typename M::Params& p, const IntegrationSettings& s,
                                const simd::mask_t<T>& fixed, StateVec<T, M::n_state>& y, T& t,
                                T& dt, const Sym<T>& deps, UpdateStats<T>& stats,
                                const simd::mask_t<T>& active) {
    using Mask = simd::mask_t<T>;
    constexpr int N = M::n_state;
    const T room = T(1.0) - t;
    const T dtl = simd::select(active, simd::min(dt, room), T(0.0));
    const Sym<T> de = voigt::scale(deps, dtl);

    const bool split = split_internal<M>(p, s);
    detail::SchemeStep<M, T> step = detail::scheme_step<M, T>(p, s, y, de, split, fixed);
    stats.rate_evaluations += simd::select(active, T(detail::scheme_evaluations(s.scheme)), T(0.0));

    const Mask valid = step.valid;
    T err;
    if (split) { // h is as accurate as its own sub-integration: the estimate is on the rest
        IntegrationSettings error_settings = s;
        error_settings.state_error_weight = 0.0;
        err = M::local_error(p, error_settings, step.low, step.kept);
    } else {
        err = M::local_error(p, s, step.low, step.kept);
    }
    err = simd::select(simd::isfinite(err), err, T(1.0e30));
    const Mask accurate = fixed || (err <= s.tolerance);
    // An admissible substep of the smallest size is taken even when it misses the tolerance
    // (a non-smooth rate, e.g. rho^beta_R at h = 0, can keep the estimate above a tight
    // tolerance at any step size); the lane is flagged unreliable instead of being cut off.
    const Mask forced = active && valid && !accurate && (dtl <= s.min_substep);
    const Mask accept = active && valid && (accurate || forced);
    stats.status =
        simd::select(forced, simd::min(stats.status, T(lane_status::unreliable)), stats.status);

    M::correct(p, step.kept);
    y = select_state<T, N>(accept, step.kept, y);
    t = simd::select(accept, t + dtl, t);
    stats.substeps += simd::select(accept, T(1.0), T(0.0));
    stats.rejected += simd::select(active && !accept, T(1.0), T(0.0));

    // Lanes that cannot take even the smallest admissible substep end in the model's
    // defined cut-off state for the rest of the increment.
    const Mask stuck = active && !accept && ((dtl <= s.min_substep) || fixed);
    if (simd::any(stuck)) {
        const Sym<T> de_rest = voigt::scale(deps, T(1.0) - t);
        const StateVec<T, N> yc = M::cut_off(p, s, y, de_rest);
        y = select_state<T, N>(stuck, yc, y);
        t = simd::select(stuck, T(1.0), t);
        stats.status =
            simd::select(stuck, simd::min(stats.status, T(lane_status::unreliable)), stats.status);
    }

    const T q = detail::controller_ratio(s.scheme, s.tolerance, err);
    const T grow = simd::min(T(s.max_step_growth), simd::max(T(s.min_step_shrink), q));
    const T shrink =
        simd::select(valid, simd::max(T(s.min_step_shrink), simd::min(q, T(0.5))), T(0.25));
    // A substep cut short by the end of the increment says nothing against the planned size.
    const Mask truncated = dt > room;
    T next = simd::select(accept, simd::select(truncated, simd::max(dt, dtl * grow), dtl * grow),
                          dtl * shrink);
    next = simd::max(next, T(s.min_substep));
    dt = simd::select(active && !fixed, next, dt);
    if (CarriesSubstep<M> && s.carry_substep) { // the carried size's estimate
        const T ideal =
            simd::select(truncated, simd::max(dt, dtl * simd::min(q, T(max_carried_growth))),
                         dtl * simd::min(q, T(max_carried_growth)));
        stats.ideal_substep =
            simd::select(accept && !forced && !fixed, ideal,
                         simd::select(stuck || forced, T(0.0), stats.ideal_substep));
    }
    return active && ((T(1.0) - t) > 1.0e-12);
}

template <class M, class T>
void integrate_explicit(const typename M::Params& p, const IntegrationSettings& s,
                        const SubstepControl<T>& control, StateVec<T, M::n_state>& y,
                        const Sym<T>& deps, UpdateStats<T>& stats) {
    using Mask = simd::mask_t<T>;
    const Mask fixed = control.fixed_substeps > 0.5;
    T t, dt;
    substep_begin<M, T>(s, control, y, deps, t, dt);
    Mask active = (T(1.0) - t) > 1.0e-12;
    for (int attempts = 0; simd::any(active) && attempts < s.max_substeps; ++attempts) {
        active = substep_attempt<M, T>(p, s, fixed, y, t, dt, deps, stats, active);
    }
    // Runaway: the lane did not finish within max_substeps. Report it; the caller cuts.
    stats.status = simd::select(active, T(lane_status::failed), stats.status);
    if (s.carry_substep) {
        carry_substep<M, T>(y, deps, stats.ideal_substep, fixed);
    }
}

} // namespace ifsim
