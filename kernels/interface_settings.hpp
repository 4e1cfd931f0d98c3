#pragma once
// Settings and per-lane data of the interface formulations (paper §3.3-3.5).
//
// Local axes of an interface point: 1 = n (normal), 2 = t1, 3 = t2. The interface stress of
// Eq. 17 in Voigt order is [sigma_N, sigma_p1, sigma_p2, tau_1, tau_2, 0] and the strain
// [eps_N, eps_p1, eps_p2, gamma_1/2, gamma_2/2, 0] (tensor shear components).

#include <array>

#include "kernels/model_api.hpp"

namespace ifsim {

// The interface formulations of a contact, in one list for every layer. Algorithm 1 runs the
// first two; coulomb is penalty friction (kernels/coulomb.hpp), routed to its own engine.
enum class InterfaceFormulation : int {
    novel = 0,  // Eqs. 17-24: sigma_p1, sigma_p2 from the extrapolated continuum stress
    stutz = 1,  // Eqs. 10-12: in-plane strains zero, Newton on eps_N only
    coulomb = 2 // Coulomb penalty friction, no continuum model
};

enum class NewtonJacobian : int {
    rate = 0,        // the model's rate stiffness at the sub-increment's start (cheap)
    perturbation = 1 // derivative of the integrated update by perturbation (consistent)
};

struct InterfaceSettings {
    InterfaceFormulation formulation = InterfaceFormulation::novel;
    int ndim = 3;                        // 2: plane strain, t2 out of plane (eps_p2 = gamma_2 = 0)
    double shear_band_thickness = 0.003; // d_s0 (m)
    double max_subincrement = 5.0e-6;    // largest shear-strain sub-increment (Algorithm 1 line 1)
    double tolerance = 2.0e-3;           // relative error of Eqs. 18-20, Algorithm 1 line 9
    bool adaptive = false;               // error-controlled sub-increments instead of fixed ones
    double adaptive_tolerance = 2.0e-3;  // local relative stress error per adaptive sub-increment
    // Adaptive sub-increments, a bound on the work per sub-increment besides the error (> 0: on).
    // An accepted sub-increment whose full solve took more Newton iterations than
    // work_newton_iterations, or whose model evaluations took more of their own substeps on
    // average than work_model_substeps, lets the next one grow at most by target / measured.
    // The error alone lets a Sanisand band take large sub-increments where each evaluation
    // costs 100-1000 substeps (the cone cap) and the rate-Jacobian Newton 45 iterations, 40x
    // the work of the paper's small ones. It only ever shrinks what the error control chose.
    // Measured on the coarse §6 runs with 8 and 4 (docs/large-scale-test.md, session 18):
    // hypoplastic band 1.8x fewer substeps, Sanisand gravity stages 6x faster. Off by default
    // until its effect on the difference Jacobians is understood: the substep count is an
    // integer, so the chosen sub-increments jump with the inputs (test_contact_jacobian_low_
    // stress moved from 1e-3 to 0.11 against central differences of whole calls).
    double work_newton_iterations = 0.0;
    double work_model_substeps = 0.0;
    int max_newton_iterations = 30;
    // Newton corrections applied after the residual of Eqs. 18-20 is below `tolerance`. The
    // paper stops at once (0). One more quadratic step leaves a residual of order tol^2, which
    // removes the chatter of the normal strains between sub-increments and makes the traction a
    // smooth function of the gap, as the perturbation Jacobian (Eq. 37) needs. See
    // docs/interface.md for the measurements behind this default.
    int polish_iterations = 1;
    long max_subincrements = 2'000'000; // per call, a guard against runaway refinement
    // The smallest sub-increment (largest shear-strain component) a failing one is cut to
    // before the lane fails or takes its second try (newton_fallback).
    double min_subincrement = 1.0e-12;
    // Per call and lane: the model's own substeps in Algorithm 1's Newton evaluations. A bound
    // on one evaluation's work (a Sanisand band at kappa = 0.05 spent 6.8e6 in one call, 90 s);
    // the drivers bound a whole step on top (max_step_substeps).
    double max_model_substeps = 1.0e6;
    NewtonJacobian newton_jacobian = NewtonJacobian::rate;
    double newton_perturbation = 1.0e-7; // relative strain perturbation of the Newton Jacobian
    // With the rate Jacobian: a lane whose residual falls by less than this factor in one
    // iteration (before it meets the tolerance) leaves the rate Jacobian for the rest of the
    // sub-increment's Newton (0: never). Near its cone a Sanisand band's rate stiffness at the
    // start state can be 20x its elastic one while the integrated response flows plastically:
    // the rate Newton then creeps (1.3e-2 -> 1.2e-2 in 11 iterations), fails, and the halving
    // only helps once the start guess alone meets the tolerance, 2^-16 of the size later; a
    // held lane goes on at that size (4.8e5 sub-increments in one call, most of them the
    // effect of polishing corrections taken far from the solution, fixed in session 19; since
    // then 1.3e4). With a Jacobian that learns the band's stiffness it converges in 2-4
    // iterations and takes 16x fewer sub-increments for the same model substeps
    // (docs/large-scale-test.md, sessions 18-19). Off by default like the work bound above. The
    // §6 Sanisand scene took 0.5 until session 28; since session 29 it backtracks instead
    // (newton_line_search): the "creeping" was a two-cycle across the yield cone.
    double newton_switch_ratio = 0.0;
    // What a creeping lane switches to: false, the perturbation Jacobian (k + 1 more evaluations
    // per iteration, each as dear as the base: the coarse hypoplastic run's contact time 2.2x);
    // true, Broyden's rank-one updates of its last Jacobian (no more evaluations).
    bool newton_switch_broyden = true;
    // Backtracking on Algorithm 1's Newton (0: the paper's plain Newton): an iterate whose
    // residual is not below the last accepted one's, or whose model update failed, is replaced
    // by one at half the step from the accepted iterate, up to this many times per step. Near
    // a Sanisand band's yield cone the response has a kink (elastic one way, plastic the
    // other), and the full steps jump across it in a two-cycle (r 0.0022 <-> 0.0123 for 30
    // iterations, whichever Jacobian; docs/large-scale-test.md, session 29). Halvings count
    // as iterations against max_newton_iterations.
    int newton_line_search = 0;
    // With the rate Jacobian: a lane that would fail because its Newton does not converge even
    // at the smallest sub-increment gets a second try instead. It goes on from its last accepted
    // sub-increment, at the call's first sub-increment size, on the perturbation Jacobian. The
    // rate stiffness at the start state can be too far from the band's true stiffness to reach
    // the targets at all (a Sanisand band near its cone, docs/large-scale-test.md), while the
    // perturbation Jacobian (k + 1 more evaluations per iteration) is too dear for every call.
    // As a last resort it leaves every call that succeeds without it bit for bit unchanged.
    bool newton_fallback = true;
    // Eq. 26 lets d_s = d_s0 (1 + eps_N) shrink towards zero in long compaction. Below this
    // fraction of d_s0 the point stops with status failed (a defined stop, never a NaN).
    double min_band_fraction = 0.05;
    // Largest change of the normal targets (t_N, s_p) per sub-increment, relative to their size.
    double max_normal_change = 0.02;
    // Contact counts as open while t_N > -open_threshold (kPa): the normal traction is the
    // penalty's; below about 1 kPa the models' stiffness vanishes with the stress
    // (hypoplasticity: p^(1-n)) and Algorithm 1 cannot follow t_N, so a touching point
    // (t_N < 0) shears its band at sigma_N = -open_threshold and its shear is scaled by
    // |t_N| / open_threshold; a separated one (t_N >= 0) keeps its state (interface_begin).
    double open_threshold = 1.0;
    // true: instead of stopping, hold d_s at min_band_fraction * d_s0 and go on (counted in
    // InterfaceStats::band_clamped). The results past that point rest on an assumed thickness.
    bool clamp_band = false;
    // the continuum model's own integration settings (contact_model_integration())
    IntegrationSettings model = contact_model_integration();
    // Adaptive runs, > 0: Algorithm 1's tolerance in the Jacobian lanes (Eq. 37 and their
    // reference re-run), solved with the perturbation Newton Jacobian. At the paper's tolerance
    // the Newton iteration count changes between lanes and puts jumps into the traction that
    // theta divides (0.17 relative column error at 3 kPa, 2.4e-4 at 1e-9). Off by default: in
    // the coarse §6 scene it cut the cuts from 22 to 5 but cost 6x the contact time
    // (docs/interface.md). 0: the lanes use `tolerance` and `newton_jacobian` like the base.
    double jacobian_tolerance = 0.0;
};

// The band thickness Algorithm 1 shears at for an interface normal strain: Eq. 26,
// d_s0 (1 + eps_N), held at min_band_fraction d_s0 when clamp_band (interface_begin). Without
// clamping a band below the floor fails its point, so the value is then never used.
inline double band_thickness(const InterfaceSettings& s, double eps_n) {
    const double d_s = s.shear_band_thickness * (1.0 + eps_n);
    const double floor = s.min_band_fraction * s.shear_band_thickness;
    return s.clamp_band && !(d_s > floor) ? floor : d_s;
}

// Codes of InterfaceStats::cause.
namespace interface_failure {
inline constexpr double none = 0.0;
inline constexpr double band_collapse = 1.0; // d_s below min_band_fraction * d_s0 (Eq. 26)
inline constexpr double non_finite_input = 2.0;
inline constexpr double newton = 3.0; // Eqs. 18-20 not met in max_newton_iterations
inline constexpr double model = 4.0;  // the constitutive update failed
inline constexpr double subincrement_limit = 5.0;
inline constexpr double singular_newton = 6.0; // d sigma_normal / d eps_normal singular (Eq. 22)
// adaptive: the step-doubling error stayed above its tolerance down to the smallest
// sub-increment (the residual field then holds that error)
inline constexpr double error_control = 7.0;
inline constexpr double work_limit = 8.0; // max_model_substeps reached (residual: substeps spent)

inline const char* describe(double cause) {
    if (cause == band_collapse) {
        return "shear band collapsed (d_s of Eq. 26 below its floor)";
    }
    if (cause == non_finite_input) {
        return "non-finite input";
    }
    if (cause == newton) {
        return "Newton on the interface normal strains did not converge (Eqs. 18-20)";
    }
    if (cause == model) {
        return "the constitutive update of the interface model failed";
    }
    if (cause == subincrement_limit) {
        return "too many sub-increments";
    }
    if (cause == work_limit) {
        return "the interface model's own substeps in one evaluation reached their bound "
               "(InterfaceSettings::max_model_substeps)";
    }
    if (cause == error_control) {
        return "the adaptive sub-increments could not meet their error tolerance down to the "
               "smallest size (the response does not become smooth as the sub-increment shrinks: "
               "often a band stress outside the interface model's limit surface)";
    }
    if (cause == singular_newton) {
        return "the Newton matrix of the interface normal strains (Eq. 22) is singular: the "
               "band's normal stiffness vanished, as on or outside the interface model's limit "
               "surface";
    }
    return "unknown";
}
// What the number that goes with a failure is ("" when none goes with it).
inline const char* residual_label(double cause) {
    if (cause == band_collapse || cause == non_finite_input) {
        return "";
    }
    if (cause == work_limit) {
        return "model substeps";
    }
    return cause == error_control ? "relative error of the smallest try" : "Algorithm 1 residual";
}
} // namespace interface_failure

// Per-lane interface state: the model state in local axes (stress = interface stress of Eq. 17),
// the interface strains, and the last accepted adaptive sub-increment (fraction of the shear
// strain increment's size in units of max_subincrement).
template <class T, int NS>
struct InterfaceState {
    StateVec<T, NS> y;
    T eps_n = T(0.0), eps_p1 = T(0.0), eps_p2 = T(0.0);
    T gamma1 = T(0.0), gamma2 = T(0.0);
    T last_subincrement = T(0.0); // 0: none yet
};

// Inputs of one evaluation (one increment of the global problem).
template <class T>
struct InterfaceInput {
    T t_N;        // normal contact stress at the end of the increment (<= 0)
    T dg1, dg2;   // tangential gap increments along t1, t2 (Eq. A13)
    T s_p1, s_p2; // extrapolated continuum stress rotated into the local frame (Eqs. 14-16)
    // > 0: take exactly this many equal sub-increments (perturbed evaluations follow the
    // discretisation of their base so a difference quotient sees no step-selection noise).
    T forced_subincrements = T(0.0);
};

template <class T>
struct InterfaceStats {
    T status = T(lane_status::ok);
    T subincrements = T(0.0); // accepted sub-increments
    T newton_iterations = T(0.0);
    T evaluations = T(0.0);      // constitutive model updates (Newton, perturbed, rejected)
    T model_substeps = T(0.0);   // substeps of the model's own integration
    T residual = T(0.0);         // final relative residual of Eqs. 18-20 (worst sub-increment)
    T open = T(0.0);             // 1: contact open (t_N >= 0), no traction, state kept
    T cause = T(0.0);            // why a lane failed: see interface_failure
    T band_clamped = T(0.0);     // 1: d_s held at its floor (clamp_band)
    T newton_fallbacks = T(0.0); // 1: the call took its second try (newton_fallback)
};

} // namespace ifsim
