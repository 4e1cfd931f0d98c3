#pragma once
// The guarded update of one batch of material points: the entry point the engine calls.
// It validates the input per lane, applies the pressure floor to a start state below it,
// integrates with the model, and leaves a failed lane exactly as it came in (status -1), so
// no NaN or half-integrated state ever leaves a kernel.

#include "kernels/explicit_integration.hpp"
#include "kernels/model_api.hpp"

namespace ifsim {

// Before integrating: validates the input (a lane with non-finite state or increment runs on a
// harmless dummy and is restored by material_finish) and lifts a start below the pressure floor
// to the isotropic floor state (status 0). Returns the increment to integrate.
template <class M, class T>
Sym<T> material_prepare(const IntegrationSettings& s, StateVec<T, M::n_state>& y,
                        const Sym<T>& deps_in, UpdateStats<T>& stats, simd::mask_t<T>& input_ok) {
    using Mask = simd::mask_t<T>;
    constexpr int N = M::n_state;
    stats = UpdateStats<T>{};
    input_ok = state_finite<T, N>(y) && voigt::all_finite(deps_in);
    const Sym<T> deps = voigt::select(input_ok, deps_in, voigt::zero<T>());
    const Sym<T> stress0 = stress_of(y);
    Mask below_floor = input_ok && (mean_pressure(stress0) < s.min_pressure);
    if constexpr (!M::pressure_floor) {
        below_floor = Mask(false);
    }
    const Sym<T> floor = voigt::scale(voigt::identity<T>(), T(-s.min_pressure));
    set_stress(y, voigt::select(below_floor, floor, voigt::select(input_ok, stress0, floor)));
    for (int i = 6; i < N; ++i) {
        y[i] = simd::select(input_ok, y[i], T(i == 6 ? 0.7 : 0.0));
    }
    stats.status = simd::select(below_floor, T(lane_status::unreliable), stats.status);
    return deps;
}

// After integrating: a lane that failed, or whose input or result is not finite, gets its
// start state back and status failed.
template <class M, class T>
void material_finish(const StateVec<T, M::n_state>& y0, StateVec<T, M::n_state>& y,
                     const simd::mask_t<T>& input_ok, UpdateStats<T>& stats) {
    constexpr int N = M::n_state;
    const simd::mask_t<T> failed = !input_ok || !state_finite<T, N>(y) || (stats.status < -0.5);
    y = select_state<T, N>(failed, y0, y);
    stats.status = simd::select(failed, T(lane_status::failed), stats.status);
}

template <class M, class T>
void material_update(const typename M::Params& p, const IntegrationSettings& s,
                     const SubstepControl<T>& control, StateVec<T, M::n_state>& y,
                     const Sym<T>& deps_in, UpdateStats<T>& stats) {
    const StateVec<T, M::n_state> y0 = y;
    simd::mask_t<T> input_ok;
    const Sym<T> deps = material_prepare<M, T>(s, y, deps_in, stats, input_ok);
    M::template integrate<T>(p, s, control, y, deps, stats);
    material_finish<M, T>(y0, y, input_ok, stats);
}

} // namespace ifsim
