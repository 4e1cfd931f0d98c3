#pragma once
// What every constitutive model of ifsim provides, and the per-lane results of an update.
//
// State layout (one flat array per point, the engine stores one SoA column per entry):
//   [0..5]  stress (kPa, Voigt 11 22 33 12 13 23, compression negative)
//   [6]     void ratio e
//   [7..]   model state (intergranular strain h, back-stress ratio alpha, fabric z, ...)
//
// A model is a struct with
//   static constexpr int n_state;               // length of the flat state
//   static constexpr const char* name;
//   static constexpr bool pressure_floor;       // lift a start below min_pressure to the floor
//   using Params = ...;                          // plain doubles, shared by a batch
//   template <class T> static void integrate(const Params&, const IntegrationSettings&,
//                                            const SubstepControl<T>&, State<T>& y,
//                                            const Sym<T>& deps, UpdateStats<T>&);
//   template <class T> static std::array<Sym<T>, 6> rate_stiffness(const Params&,
//                                            const IntegrationSettings&, const State<T>&,
//                                            const Sym<T>& deps);
// integrate() integrates the strain increment deps from y in place; it never throws, allocates
// or prints. Failure is reported per lane in UpdateStats::status. The engine calls it through
// material_update() (kernels/material_update.hpp), which validates the input.

#include <array>
#include <concepts>
#include <cstddef>

#include "kernels/voigt.hpp"

namespace ifsim {

template <class T, std::size_t N>
using StateVec = std::array<T, N>;

namespace state_index {
inline constexpr int stress = 0;
inline constexpr int void_ratio = 6;
inline constexpr int model = 7;
} // namespace state_index

// Lane status codes (MGIS style): stored as doubles in the lanes.
namespace lane_status {
inline constexpr double failed = -1.0;    // no usable result: state left unchanged
inline constexpr double unreliable = 0.0; // a safeguard acted (tension cut-off, step floor)
inline constexpr double ok = 1.0;
} // namespace lane_status

// Explicit scheme of the adaptive substepping (kernels/explicit_integration.hpp).
enum class IntegrationScheme {
    heun,  // modified Euler 1(2): 2 rate evaluations per substep, error of the Euler result
    rkf23, // Runge-Kutta-Fehlberg 2(3): 3 evaluations, error of the 2nd-order result,
           // the 3rd-order result kept (local extrapolation)
};

struct IntegrationSettings {
    IntegrationScheme scheme = IntegrationScheme::rkf23;
    double tolerance = 1.0e-3; // accepted relative local error of one substep
    // Weight of the model's internal state (hypoplasticity: h / R) in the local error beside
    // stress and void ratio; 0 = stress and void ratio only (docs/accuracy.md).
    double state_error_weight = 1.0;
    // Start each update from the substep size the point ended its last one with (models that
    // carry it, kernels/explicit_integration.hpp); false: from control.initial_substep.
    bool carry_substep = true;
    // Integrate a decoupled internal state (hypoplasticity's h, whose rate depends on h and the
    // strain only) on its own, to the tolerance, inside each substep of the stress
    // (kernels/explicit_integration.hpp); false: all of the state in one scheme.
    bool split_internal = true;
    // Sanisand only: backward-Euler steps (kernels/sanisand_implicit.hpp) instead of explicit
    // substeps; the scene readers reject it for the other models.
    bool backward_euler = false;
    double min_substep = 1.0e-9;  // smallest substep, as a fraction of the increment
    int max_substeps = 200000;    // guard against runaway step collapse
    double min_pressure = 1.0e-3; // kPa; below this mean stress the tension cut-off acts
    double max_step_growth = 2.0; // largest growth factor of the substep size
    double min_step_shrink = 0.1; // smallest shrink factor of the substep size
};

// The integration the interface models of the contact engine use (Algorithm 1 and its
// Jacobian lanes): modified Euler with h in the same scheme and no carried substep. The Eq. 37
// lanes difference adaptive model updates, so a flipped step decision moves a traction by the
// kept result's error: Heun keeps ~0.1 tol, RKF23 ~tol (Eq. 37 columns 100 % off at 1.5-10 kPa
// in tests/engine/test_contact_jacobian_low_stress.cpp at 1e-3; fine at 1e-5, but slower than
// Heun there). docs/accuracy.md, "Continuum integration".
inline IntegrationSettings contact_model_integration() {
    IntegrationSettings s;
    s.scheme = IntegrationScheme::heun;
    s.split_internal = false;
    s.carry_substep = false;
    return s;
}

template <class T>
struct UpdateStats {
    T status = T(lane_status::ok);
    T substeps = T(0.0);         // accepted substeps
    T rejected = T(0.0);         // rejected substeps
    T rate_evaluations = T(0.0); // evaluations of the rate equations
    // Step controller's estimate of the largest substep meeting the tolerance after the last
    // accepted substep, as a fraction of this increment (0 = no estimate: fixed or cut off).
    T ideal_substep = T(0.0);
};

template <class M>
concept ConstitutiveModel = requires {
    typename M::Params;
    { M::n_state } -> std::convertible_to<int>;
    { M::name } -> std::convertible_to<const char*>;
};

template <class T, std::size_t N>
inline Sym<T> stress_of(const StateVec<T, N>& y) {
    return {y[0], y[1], y[2], y[3], y[4], y[5]};
}
template <class T, std::size_t N>
inline void set_stress(StateVec<T, N>& y, const Sym<T>& s) {
    for (int i = 0; i < 6; ++i) {
        y[i] = s[i];
    }
}
template <class T, std::size_t N>
inline Sym<T> sym_at(const StateVec<T, N>& y, int offset) {
    return {y[offset], y[offset + 1], y[offset + 2], y[offset + 3], y[offset + 4], y[offset + 5]};
}
template <class T, std::size_t N>
inline void set_sym_at(StateVec<T, N>& y, int offset, const Sym<T>& s) {
    for (int i = 0; i < 6; ++i) {
        y[offset + i] = s[i];
    }
}
template <class T, std::size_t N>
inline StateVec<T, N> select_state(const simd::mask_t<T>& m, const StateVec<T, N>& a,
                                   const StateVec<T, N>& b) {
    StateVec<T, N> r;
    for (std::size_t i = 0; i < N; ++i) {
        r[i] = simd::select(m, a[i], b[i]);
    }
    return r;
}
template <class T, std::size_t N>
inline simd::mask_t<T> state_finite(const StateVec<T, N>& y) {
    auto m = simd::isfinite(y[0]);
    for (std::size_t i = 1; i < N; ++i) {
        m = m && simd::isfinite(y[i]);
    }
    return m;
}
// Mean pressure p = -tr(sigma)/3, positive in compression.
template <class T>
inline T mean_pressure(const Sym<T>& s) {
    return -(s[0] + s[1] + s[2]) * (1.0 / 3.0);
}

} // namespace ifsim
