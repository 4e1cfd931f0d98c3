#pragma once
// The element-test driver: one material point taken through stages of mixed strain/stress
// control (scene kind "element-test"). Each step prescribes the strain increment of the
// strain-controlled components and solves for the others by a Newton iteration on the stress
// targets, with the tangent by perturbation of the integrated update (the 6 perturbed updates
// are lanes of one batched update, like the contact points' perturbations) or the model's
// cheap rate stiffness.

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "engine/batched_update.hpp"
#include "engine/model_registry.hpp"
#include "engine/tangent_kind.hpp"

namespace ifsim {

struct ElementStage {
    int steps = 1;
    std::array<bool, 6> stress_controlled{}; // true: dsig_IJ given, false: deps_IJ given
    Sym<double> change{};                    // total change over the stage (strain or stress)
    // Newton's first guess of the first step's strain increment (stress-controlled components;
    // later steps start from the step before). A replay of a failed step sets it to the guess
    // the run had (io/element_test/element_replay.hpp).
    Sym<double> first_guess{};
};

struct ElementTestSettings {
    UpdateOptions update; // SIMD/scalar, integration tolerance etc.
    TangentKind tangent = TangentKind::perturbation;
    double newton_tolerance = 1.0e-8; // stress residual / max(|sigma|, 1 kPa)
    int max_newton_iterations = 40;
    double perturbation = 1.0e-7; // relative strain perturbation of the tangent
};

struct ElementRow {
    int step = 0;
    int stage = 0;
    Sym<double> strain{};
    std::vector<double> state; // the model's flat state (model_api.hpp layout)
};

struct ElementTestCounters {
    long increments = 0;
    long newton_iterations = 0;
    double substeps = 0.0;
    double rejected_substeps = 0.0;
    double rate_evaluations = 0.0;
    long constitutive_evaluations = 0;
    long unreliable_updates = 0;     // a safeguard (pressure floor / tension cut-off) acted
    long frozen_substep_retries = 0; // steps solved again with frozen substeps (solve_step)
};

struct ElementTestResult {
    bool ok = true;
    std::string reason; // why it failed (step, stage, what)
    ElementTestCounters counters;
    double constitutive_seconds = 0.0; // time inside the batched updates
    double driver_seconds = 0.0;       // Newton bookkeeping around them
};

// Where a run stands after a committed step: all a resumed run needs to continue bit for bit
// (checkpoint and resume, docs/scenes.md).
struct ElementTestPosition {
    int stage = 0;         // 0-based stage of the last committed step
    int step_in_stage = 0; // steps of that stage done
    int step = 0;          // steps done in all
    std::vector<double> state;
    Sym<double> strain{};
    Sym<double> guess{};        // the next step's first guess of the unknown strains
    Sym<double> stress_start{}; // the stage's stress targets start here
};

// Runs all stages from the initial state, or from `resume` (then no row 0 is written). on_row
// is called for step 0 and after every step, then on_step with the position after it; a
// failure stops the run with result.ok = false and a reason naming step and stage. The
// counters count the work of this call. Throws std::invalid_argument for an initial state of
// the wrong length.
ElementTestResult
run_element_test(const MaterialChoice& material, const std::vector<double>& initial_state,
                 const std::vector<ElementStage>& stages, const ElementTestSettings& settings,
                 const std::function<void(const ElementRow&)>& on_row,
                 const ElementTestPosition* resume = nullptr,
                 const std::function<void(const ElementTestPosition&)>& on_step = {});

} // namespace ifsim
