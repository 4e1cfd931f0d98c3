#pragma once
// Explicit integration of a rate-type constitutive model over one strain increment:
// modified Euler (Heun) with local error control (Sloan type), per lane.
//
// Pseudo-time t in [0, 1] runs over the increment; a substep of size dt applies the strain
// dt * deps. Each lane keeps its own t and dt, so lanes of a SIMD batch take different substeps;
// finished lanes stay masked until the slowest lane of the batch is done.
//
// The model M provides (all templates over T, no allocation, no throwing):
//   State euler_increment(p, s, y, de)  increment of the state for the strain increment de
//   T     local_error(p, y, yE, yH)     relative error between the Euler and Heun results
//   mask  admissible(p, s, y)           state may be used (finite, pressure above the floor)
//   void  correct(p, y)                 projection after an accepted substep (drift, |h| <= R)
//   State cut_off(p, s, y, de_rest)     defined end state when no substep is admissible

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

// Start of an increment: pseudo-time 0 and the first substep size.
template <class T>
void heun_begin(const IntegrationSettings& s, const SubstepControl<T>& control, T& t, T& dt) {
    const simd::mask_t<T> fixed = control.fixed_substeps > 0.5;
    t = T(0.0);
    dt = simd::select(fixed, 1.0 / simd::max(control.fixed_substeps, T(1.0)),
                      simd::min(simd::max(control.initial_substep, T(s.min_substep)), T(1.0)));
}

// One substep attempt for every active lane: accepted lanes advance t and y, rejected ones
// shrink dt; a lane that cannot take even the smallest admissible substep ends in the model's
// cut-off state. Returns the lanes still active afterwards.
template <class M, class T>
simd::mask_t<T> heun_attempt(const typename M::Params& p, const IntegrationSettings& s,
                             const simd::mask_t<T>& fixed, StateVec<T, M::n_state>& y, T& t, T& dt,
                             const Sym<T>& deps, UpdateStats<T>& stats,
                             const simd::mask_t<T>& active) {
    using Mask = simd::mask_t<T>;
    constexpr int N = M::n_state;
    const T dtl = simd::select(active, simd::min(dt, T(1.0) - t), T(0.0));
    const Sym<T> de = voigt::scale(deps, dtl);

    const StateVec<T, N> k1 = M::euler_increment(p, s, y, de);
    StateVec<T, N> yE;
    for (int i = 0; i < N; ++i) {
        yE[i] = y[i] + k1[i];
    }
    const StateVec<T, N> k2 = M::euler_increment(p, s, yE, de);
    StateVec<T, N> yH;
    for (int i = 0; i < N; ++i) {
        yH[i] = y[i] + 0.5 * (k1[i] + k2[i]);
    }
    stats.rate_evaluations += simd::select(active, T(2.0), T(0.0));

    const Mask valid = M::admissible(p, s, yE) && M::admissible(p, s, yH);
    T err = M::local_error(p, y, yE, yH);
    err = simd::select(simd::isfinite(err), err, T(1.0e30));
    const Mask accurate = fixed || (err <= s.tolerance);
    // An admissible substep of the smallest size is taken even when it misses the tolerance
    // (a non-smooth rate, e.g. rho^beta_R at h = 0, can keep the estimate above a tight
    // tolerance at any step size); the lane is flagged unreliable instead of being cut off.
    const Mask forced = active && valid && !accurate && (dtl <= s.min_substep);
    const Mask accept = active && valid && (accurate || forced);
    stats.status =
        simd::select(forced, simd::min(stats.status, T(lane_status::unreliable)), stats.status);

    M::correct(p, yH);
    y = select_state<T, N>(accept, yH, y);
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

    const T q = 0.9 * simd::sqrt(s.tolerance / simd::max(err, T(1.0e-30)));
    const T grow = simd::min(T(s.max_step_growth), simd::max(T(s.min_step_shrink), q));
    const T shrink =
        simd::select(valid, simd::max(T(s.min_step_shrink), simd::min(q, T(0.5))), T(0.25));
    T next = simd::select(accept, dtl * grow, dtl * shrink);
    next = simd::max(next, T(s.min_substep));
    dt = simd::select(active && !fixed, next, dt);
    return active && ((T(1.0) - t) > 1.0e-12);
}

template <class M, class T>
void integrate_heun(const typename M::Params& p, const IntegrationSettings& s,
                    const SubstepControl<T>& control, StateVec<T, M::n_state>& y,
                    const Sym<T>& deps, UpdateStats<T>& stats) {
    using Mask = simd::mask_t<T>;
    const Mask fixed = control.fixed_substeps > 0.5;
    T t, dt;
    heun_begin(s, control, t, dt);
    Mask active = (T(1.0) - t) > 1.0e-12;
    for (int attempts = 0; simd::any(active) && attempts < s.max_substeps; ++attempts) {
        active = heun_attempt<M, T>(p, s, fixed, y, t, dt, deps, stats, active);
    }
    // Runaway: the lane did not finish within max_substeps. Report it; the caller cuts.
    stats.status = simd::select(active, T(lane_status::failed), stats.status);
}

} // namespace ifsim
