#pragma once
// The point-level simple interface shear test (scene kind "interface-test", paper §5): one
// continuum material point (the sample, height H) in series with one interface point. Both
// carry the same normal stress t_N and shear stress tau; the sample's in-plane strains are zero
// (rigid box); the plate's tangential displacement is the interface slip plus the sample's
// shear: du_t = dg_T + 2 deps_12 H. Normal control: CNL (t_N constant) or CNS
// (t_N = t_N0 - K u_n with u_n = eps_11 H of the sample).
//
// Each step solves for (dg_T1, dg_T2, deps_11) by Newton's method, with the interface traction
// Jacobian of the contact engine (Eq. 37 lanes, or the scene's scheme) and the sample's tangent
// by perturbation. Local axes: 1 = interface normal, 2 = t1, 3 = t2.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "engine/batched_update.hpp"
#include "engine/contact_update.hpp"
#include "engine/failed_contact_point.hpp"
#include "engine/model_registry.hpp"
#include "kernels/coulomb.hpp"

namespace ifsim {

enum class NormalControl { constant_stress, constant_stiffness };

struct InterfaceStage {
    int steps = 1;
    double du_t1 = 0.0; // plate tangential displacement change over the stage (m)
    double du_t2 = 0.0;
};

struct InterfaceTestSpec {
    MaterialChoice interface_material;   // continuum model used as interface model (not coulomb)
    std::vector<double> interface_state; // its initial state (local axes, model layout)
    CoulombParams coulomb;               // contact.interface.formulation == coulomb
    MaterialChoice sample_material;
    std::vector<double> sample_state; // initial sample state (local axes)
    double height = 0.02;             // sample height H (m)
    NormalControl control = NormalControl::constant_stress;
    double normal_stiffness = 0.0; // K (kPa/m), CNS only
    ContactOptions contact;        // formulation, sub-increments, Jacobian scheme, SIMD
    // The sample's integration settings, SIMD; by default the interface model's (both are the
    // same soil in a series system, kernels/model_api.hpp contact_model_integration()).
    UpdateOptions sample_update = [] {
        UpdateOptions o;
        o.settings = contact_model_integration();
        return o;
    }();
    // Relative residual of the step equations, |R| / max(|t_N|, 1 kPa). The interface response
    // is only piecewise smooth (sub-increment counts, Newton stops, loading branches of the
    // model), with jumps of up to ~2e-5 relative measured: tighter tolerances can stall.
    double newton_tolerance = 1.0e-4;
    // A step whose Newton ran out of iterations with valid evaluations (also after the frozen
    // retry) is accepted at its best iterate when that residual is at most this: the noise
    // floor of the inner solves a tight newton_tolerance cannot get below (counted in
    // stagnation_accepts). 0: never (the scene reader sets it to newton_tolerance, also off).
    double stagnation_tolerance = 0.0;
    int max_newton_iterations = 40;
    // Work bound of one step (its cuts included): the interface model's substeps in the base
    // evaluations of Algorithm 1 (counters.model_substeps; the Eq. 37 lanes are not counted). Past
    // it the run stops with a message naming step and bound instead of running on for minutes (6 mm
    // of slip in one novel step did not end). 1e7 substeps are 20-60 s of one core; a 6 mm Stutz
    // step needs 3.5e6.
    double max_step_substeps = 1.0e7;
    std::vector<InterfaceStage> stages;
};

struct InterfaceRow {
    int step = 0, stage = 0;
    double u_t1 = 0, u_t2 = 0, u_n = 0, t_n = 0, t_t1 = 0, t_t2 = 0;
    double s_n = 0, s_p1 = 0, s_p2 = 0, eps_n = 0, eps_p1 = 0, eps_p2 = 0;
    double gamma1 = 0, gamma2 = 0, band_thickness = 0;
    double sample_s11 = 0, sample_s22 = 0, sample_s33 = 0, sample_s12 = 0, sample_s13 = 0;
    double e_interface = 0, e_sample = 0;
    double slip1 = 0, slip2 = 0; // accumulated interface slip g_T (m)
    int newton_iterations = 0;   // of this step
};

struct InterfaceTestCounters {
    long increments = 0;
    long newton_iterations = 0;
    long step_cuts = 0;          // halvings of steps whose Newton failed
    long band_clamped_steps = 0; // steps in which d_s was held at its floor (clamp_band)
    long frozen_retries = 0;     // step solves redone with their first discretisation frozen
    // step solves accepted at a stalled residual <= stagnation_tolerance
    long stagnation_accepts = 0;
    double subincrements = 0.0; // Algorithm 1 sub-increments (base evaluations)
    double interface_newton_iterations = 0.0;
    double constitutive_evaluations = 0.0; // interface (all lanes) + sample
    double interface_evaluations = 0.0;
    double sample_evaluations = 0.0;
    double model_substeps = 0.0;
    // Algorithm 1 calls that took their second try (newton_fallback), every evaluation
    double interface_newton_fallbacks = 0.0;
};

struct InterfaceTestResult {
    bool ok = true;
    std::string reason;
    InterfaceTestCounters counters;
    double interface_seconds = 0.0; // inside the contact engine
    double sample_seconds = 0.0;    // inside the sample's batched updates
    double driver_seconds = 0.0;
    // A run that failed because its interface point failed in Algorithm 1: that evaluation,
    // for a replay (io/replay/interface_replay.hpp).
    std::optional<FailedContactPoint> failed_point;
};

// Where a run stands after a committed step: all a resumed run needs to continue bit for bit
// (checkpoint and resume, docs/scenes.md).
struct InterfaceTestPosition {
    int stage = 0;         // 0-based stage of the last committed step
    int step_in_stage = 0; // steps of that stage done
    int step = 0;          // steps done in all
    std::vector<double> sample_state;
    // The interface point's committed state: model state and interface strains (continuum
    // interface), or the shear tractions (Coulomb).
    std::vector<double> interface_state;
    double u_t[2] = {0.0, 0.0};
    double slip[2] = {0.0, 0.0};
    double eps11 = 0.0;
    double guess_g[2] = {0.0, 0.0}; // the next step's first guess
    double guess_e11 = 0.0;
};

// Runs all stages, or the rest from `resume` (then no row 0 is written); on_row for step 0
// and after every step, then on_step with the position after it. A failure stops the run with
// ok = false and a reason naming step, stage and cause. The counters count the work of this
// call. Throws std::invalid_argument for inconsistent input (state lengths).
InterfaceTestResult
run_interface_test(const InterfaceTestSpec& spec,
                   const std::function<void(const InterfaceRow&)>& on_row,
                   const InterfaceTestPosition* resume = nullptr,
                   const std::function<void(const InterfaceTestPosition&)>& on_step = {});

} // namespace ifsim
