#pragma once
// Implicit static analysis, small strain: stages of increments, a Newton-Raphson iteration per
// increment, increment cutting on failure.
//
// One Newton iteration (phases timed separately):
//   element  - strain increments at every integration point from the displacement increment,
//              the batched constitutive update of each element set (one MaterialPoints of the
//              set's model), and the material tangent (perturbation lanes or rate stiffness);
//   assembly - element internal forces and tangents (plus hourglass control), scattered into
//              the full force vector and the reduced sparse matrix colour by colour; springs;
//              residual R = f_ext - f_int on the equations;
//   solve    - numeric factorisation (symbolic analysis once per pattern) and solve.
// Converged: the trial states are committed (swap) and the displacements updated. Not
// converged in max_iterations, a material point failed, or a singular system: nothing is
// committed and the increment is halved, up to max_cuts times, then the stage fails with a
// reason naming stage, step and pseudo-time.

#include <array>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "fem/contact_pair.hpp"
#include "fem/contact_set.hpp"
#include "fem/continuum_assembly.hpp"
#include "fem/dof_map.hpp"
#include "fem/element_geometry.hpp"
#include "fem/linear_solver.hpp"
#include "fem/mesh.hpp"
#include "fem/solver_settings.hpp"
#include "fem/sparse_system.hpp"
#include "fem/stage.hpp"
#include "fem/stage_loads.hpp"

namespace ifsim::fem {

struct SolverCounters {
    long increments = 0;                // converged (committed) increments
    long cuts = 0;                      // increments halved after a failure
    long newton_iterations = 0;         // linear solves of the Newton iteration
    long constitutive_evaluations = 0;  // point updates incl. perturbation lanes
    long tangent_evaluations = 0;       // of which perturbation lanes
    long tangent_fallbacks = 0;         // points whose perturbation lanes failed (rate used)
    long failed_point_updates = 0;      // base updates with status failed
    long unreliable_point_updates = 0;  // committed point updates on which a safeguard acted
    long patterns_built = 0;            // sparse patterns (one per distinct DOF map)
    long gravity_load_builds = 0;       // unit gravity vectors integrated
    long gravity_load_applications = 0; // evaluations with gravity in the external force
    long pressure_load_builds = 0;
    long k0_points = 0;        // integration points given a K0 initial stress
    long geometry_updates = 0; // updated Lagrangian: element geometries rebuilt
    // Contact (all pairs): pairings, engine updates and what they cost.
    long contact_pairings = 0;
    long contact_pattern_rebuilds = 0; // patterns rebuilt because the pairing changed
    long contact_evaluations = 0;      // engine updates (one per residual evaluation and pair)
    double contact_point_updates = 0.0;
    double contact_lanes = 0.0;         // Algorithm 1 runs incl. Jacobian lanes
    double contact_subincrements = 0.0; // Algorithm 1 sub-increments (base lanes)
    double contact_constitutive_evaluations = 0.0;
    double contact_model_substeps = 0.0; // substeps of the interface models' own integration
    long contact_failures = 0;   // engine updates with a failed point (the increment was cut)
    long line_search_steps = 0;  // residual passes spent halving Newton steps
    long stagnation_accepts = 0; // increments accepted at the inner solves' noise floor
    long divergence_cuts = 0;    // increments cut early: their Newton could not converge in time
    double worst_accepted_residual = 0.0; // largest relative residual of an accepted increment
    long increment_growths = 0;           // increments doubled back towards the nominal step
    long predictor_solves = 0;            // tangent predictors (one solve each)
    long predictor_fallbacks = 0;         // tangent predictors not formed (zero guess)
    long predictor_rejections = 0;    // tangent guesses whose residual was above the zero guess's
    long gathers = 0;                 // re-gathers of the in-plane targets (implicit gather)
    double worst_gather_change = 0.0; // largest target change left in an accepted increment
    long partition_solves = 0;        // Newton solves run again for released sub-increments
    long partition_releases = 0;      // contact points whose held sub-increments were released
    long contact_relaxed_reruns = 0;  // see ContactPairCounters
    double contact_relaxed_point_updates = 0.0;
    long viscous_increments = 0;    // increments committed on a retry with the slip viscosity
    long viscous_holds = 0;         // of those, taken at once (SolverSettings::hold_slip_viscosity)
    long viscous_hold_failures = 0; // held increments that failed and were solved without it
    double contact_viscous_point_updates = 0.0; // slip viscosity (ContactPairCounters)
    double contact_viscous_share_max = 0.0;
    double contact_viscous_traction_max = 0.0;
    long contact_band_clamped = 0;      // point evaluations on a clamped band (clamp_band = true)
    double contact_dropped_lanes = 0.0; // failed Jacobian lanes (the point took Eq. B3's columns)
    double contact_newton_fallbacks = 0.0; // Algorithm 1 calls on their second try
    LinearSolverCounters linear;
};

struct SolverTimers {
    double element = 0.0;  // strains, constitutive update, material tangent
    double assembly = 0.0; // element vectors/matrices, scatter, residual
    double solve = 0.0;    // factorisation and solve
    double gravity = 0.0;  // building and scaling the gravity load
    double k0 = 0.0;       // initial K0 stress
    double pressure = 0.0; // building and scaling face pressures
    // Contact, summed over the pairs (paper Table 5 split).
    double contact_search = 0.0;  // pairing: projection onto the master surface
    double contact_gather = 0.0;  // frames, extrapolated stresses, gaps into the engine arrays
    double contact_kernels = 0.0; // the contact engines' batched updates
    double contact_scatter = 0.0; // tractions to nodal forces, tangent entries into the matrix
};

// Where the increment control of a stage stands: the nominal step, the start of the next
// increment in it, the halvings in force and the converged increments since the last change
// (a committed increment's `next`, from which a resumed run continues).
struct StageCursor {
    int step = 1;
    double t_a = 0.0;
    int depth = 0;
    int streak = 0;
    double step_substeps = 0.0; // interface-model substeps the step had spent (its work bound)
    bool viscous_held = false;  // the next increment takes the slip viscosity at once
    // SolverSettings::carry_cuts: the cut depth this step started at, and the steps in a row
    // before it that ended at the depth they started at.
    int start_depth = 0;
    int calm_steps = 0;
};

struct IncrementInfo {
    int stage = 0; // 1-based count of run_stage calls
    int step = 0;  // nominal step of the stage (1-based)
    double t_begin = 0.0;
    double t_end = 0.0;
    int cut_depth = 0;               // halvings of the nominal step for this increment
    int line_search_steps = 0;       // residual passes spent halving Newton steps
    bool stagnated = false;          // accepted at the inner solves' noise floor
    int gathers = 0;                 // re-gathers of the in-plane targets
    double gather_change = 0.0;      // the last re-gather's largest relative target change
    int partition_solves = 0;        // solves run again for released sub-increments
    std::vector<double> residuals;   // relative residual at each evaluation
    std::vector<double> corrections; // relative correction of each Newton iteration
    StageCursor next;                // after a converged increment: where the stage goes on
};

// One Newton iteration's tangent against central differences of the residual along the
// Newton direction c (settings.check_tangent): (R(u + h c) - R(u - h c)) / 2h against -K c,
// scaled so that the largest entry of h c is `step` metres. `mismatch` is the relative norm
// of the difference, `pairs` the same for each contact pair's own forces and tangent entries,
// `rest` for everything else.
struct TangentCheckRecord {
    int stage = 0;
    double t_end = 0.0;
    int iteration = 0;
    double step = 0.0;
    double mismatch = 0.0;
    int worst_dof = -1; // global DOF (dim * node + direction) of the largest difference
    double worst_difference = 0.0, worst_tangent = 0.0;
    std::vector<double> pairs; // per contact pair, in the order they were added
    // The rest (continuum, springs, loads): the global differences minus the pairs'.
    double rest = 0.0;
    int rest_worst_dof = -1;
};

// The out-of-balance force of the initial state (stresses, loads and supports of the first
// stage at its start, before any increment): an initial stress that the boundary conditions do
// not hold (e.g. a lateral stress on a free side face) shows here, and the first increments
// then spend themselves on finding equilibrium instead of on the load path.
struct InitialImbalance {
    bool evaluated = false;
    double relative = 0.0; // ||R|| / F_ref
    int node = -1;         // node and direction of the largest entry
    int direction = -1;
    double force = 0.0; // kN (per m in 2D)
};

// The committed state of a run between increments, everything the next increments depend
// on (checkpoints: io/boundary_value/boundary_value_checkpoint.cpp). Counters and timers are
// not part of it.
struct SolverSnapshot {
    int stage_count = 0; // run_stage calls so far, the running stage's included
    std::vector<double> u, u_stage_start, du_last, f_int_committed, f_ext_committed;
    double dt_last = 0.0;
    double reference_sum = 0.0;
    long committed_references = 0;
    std::vector<double> material_states; // every set's points, n_state values each
    std::vector<ContactPairSnapshot> contacts;
    std::vector<std::vector<double>> spring_references; // the running stage's springs
    InitialImbalance imbalance;
};

struct StageResult {
    bool ok = true;
    std::string reason;
    int increments = 0;
};

class StaticSolver {
public:
    // Throws std::invalid_argument for an invalid mesh, an element without material or in two
    // sets, an initial state of the wrong length, or an inverted element.
    StaticSolver(Mesh mesh, std::vector<ElementSetMaterial> materials, SolverSettings settings);
    ~StaticSolver();

    using IncrementCallback = std::function<void(const IncrementInfo&)>;
    // on_increment after every converged increment; on_iteration after every residual
    // evaluation of an increment attempt (progress of long increments).
    StageResult run_stage(const Stage& stage, const IncrementCallback& on_increment = {},
                          const IncrementCallback& on_iteration = {});
    // The committed state, and a run continued from one: restore() prepares `stage` (the one
    // the snapshot was taken in) as its start did, then sets the committed state; the stage
    // then goes on with resume_stage() from the increment's `next` cursor.
    SolverSnapshot snapshot() const;
    void restore(const Stage& stage, const SolverSnapshot& snapshot);
    StageResult resume_stage(const Stage& stage, const StageCursor& from,
                             const IncrementCallback& on_increment = {},
                             const IncrementCallback& on_iteration = {});

    // Committed results.
    const std::vector<double>& displacement() const { return u_; }
    // Internal forces (incl. springs) at the last converged state, full length; at prescribed
    // DOFs minus the external load this is the reaction.
    const std::vector<double>& internal_force() const { return f_int_committed_; }
    // External loads (gravity, pressures) at the last converged state, full length.
    const std::vector<double>& external_force() const { return f_ext_committed_; }
    std::vector<double> state(int element, int point) const;       // committed
    std::vector<double> trial_state(int element, int point) const; // last evaluation
    int points_per_element() const { return continuum_->geometry().nip; }
    const Mesh& mesh() const { return mesh_; }
    const ElementGeometry& geometry() const { return continuum_->geometry(); }
    const SolverCounters& counters() const;
    const InitialImbalance& initial_imbalance() const { return imbalance_; }
    SolverTimers timers() const; // the solver's phases plus the contact pairs'

    // Adds a contact pair on two face sets of the mesh (before the first stage). Throws
    // std::invalid_argument for unknown face sets or invalid settings, std::logic_error after
    // the first stage.
    void add_contact(ContactPairSpec spec);
    const std::vector<std::unique_ptr<ContactPair>>& contacts() const { return contacts_.pairs(); }
    // The pairs' counters summed (what counters() reports as contact_*).
    ContactSetCounters contact_counters() const { return contacts_.counters(); }
    const SolverSettings& settings() const { return settings_; }

    // Probing (tests, diagnostics): prepare a stage without running it, then evaluate the
    // reduced residual and optionally the tangent at a trial increment (full DOF vector) for
    // the loads at pseudo-time t, from the committed state. Nothing is committed.
    void begin_stage(const Stage& stage);
    bool evaluate(double t, std::span<const double> increment, bool with_tangent,
                  std::string& error);
    const DofMap& dof_map() const { return dofs_; }
    const std::vector<double>& residual() const { return residual_; }
    const Eigen::SparseMatrix<double>& tangent_matrix() const { return system_->matrix(); }
    const std::vector<TangentCheckRecord>& tangent_checks() const { return tangent_checks_; }

private:
    bool solve_increment(double t_begin, double t_end, IncrementInfo& info, std::string& error,
                         const IncrementCallback& on_iteration);
    // First guess of the increment: prescribed DOFs at their new values, free DOFs by the
    // settings' predictor; residual_current when the residual of the guess is already formed.
    void first_guess(double t_begin, double t_end, bool& residual_current);
    // First guess of the free DOFs by the tangent at the committed state (du_ in and out:
    // the prescribed DOFs set, the free ones zero on entry). False (with the reason) when
    // the committed state cannot be evaluated or its tangent not factorised.
    bool tangent_predictor(double t_end, std::string& error);
    void zero_free_dofs(); // du_: prescribed_du_ on prescribed DOFs, zero elsewhere
    // x = K^-1 b with the assembled tangent: by GMRES on the held factorisation
    // (settings.reuse_factorisation) to the relative residual min(krylov_tolerance,
    // forcing) or, failing that, a new factorisation.
    bool solve_tangent_system(const double* b, double* x, double forcing, std::string& error);
    // One Newton step from du_: solve with the tangent at du_, then backtrack on the residual
    // norm; rel in: the residual at du_, out: at the new iterate.
    bool newton_step(double t_end, double& rel, double& correction, IncrementInfo& info,
                     std::string& error);
    bool residual_pass(double t, std::span<const double> du, std::string& error);
    // False (with the message) once the nominal step under way spent more interface-model
    // substeps than SolverSettings::max_step_substeps allows; sets step_over_budget_.
    bool within_step_budget(std::string& error);
    // settings.check_tangent: records the tangent at du_ against central differences along
    // the solved correction; leaves residual_ and the force level as they were.
    void check_tangent(double t_end, const IncrementInfo& info);
    void tangent_pass(std::span<const double> du, PrescribedCoupling* coupling = nullptr);
    // Pairs every contact at the committed configuration and gathers its stresses; rebuilds
    // the sparse pattern when the stage's DOF map or a pairing changed.
    void begin_contacts(bool dofs_changed);
    ElementStresses stresses(bool trial) const;
    // After Newton converged: re-gathers the in-plane targets; true when they settled. A
    // probe (the early gather) keeps the old targets when they settled.
    bool targets_settled(IncrementInfo& info, std::string& error, bool probe = false);
    // After Newton converged with held sub-increments (ContactPairSpec::hold_partition): true
    // when points whose slip outgrew theirs were released, so that one more solve runs with
    // sub-increments chosen for the converged slip (at most max_partition_solves per increment;
    // the slip only grows between them, so the count is a guard, not a limit reached in practice).
    bool partitions_released(IncrementInfo& info);
    static constexpr int max_partition_solves = 3;
    void commit_increment(double dt);
    StageResult stage_from(const Stage& stage, StageCursor from,
                           const IncrementCallback& on_increment,
                           const IncrementCallback& on_iteration);
    void measure_initial_imbalance();

    Mesh mesh_;
    SolverSettings settings_;
    std::unique_ptr<ContinuumAssembly> continuum_;
    ContactSet contacts_;
    StageLoads loads_;

    // Stage data.
    std::optional<Stage> stage_; // the running stage (a copy)
    int stage_count_ = 0;
    DofMap dofs_;
    std::unique_ptr<SparseSystem> system_;
    LinearSolver linear_;
    // Reuse of the held factorisation (settings.reuse_factorisation), in preconditioner
    // applications: the Krylov steps spent since the last factorisation and the solves made
    // with it; stale: the next system is factorised directly (so at every increment start).
    long krylov_steps_since_factorisation_ = 0;
    long solves_since_factorisation_ = 0;
    bool factorisation_stale_ = false;
    std::vector<double> u_stage_start_;

    // Displacements and forces.
    std::vector<double> u_;            // committed
    std::vector<double> du_;           // trial increment
    std::vector<double> du_last_;      // last converged increment of the stage
    std::vector<double> du_start_;     // the iterate a line search starts from
    double dt_last_ = 0.0;             // its pseudo-time length (0: none yet)
    double step_substeps_start_ = 0.0; // interface-model substeps when the nominal step began
    bool budget_active_ = false;       // inside stage_from's steps
    bool step_over_budget_ = false;
    std::string budget_error_;
    std::vector<double> f_int_; // trial internal force, full
    std::vector<double> f_int_committed_;
    std::vector<double> f_ext_;
    std::vector<double> f_ext_committed_;
    std::vector<double> residual_;   // reduced
    std::vector<double> correction_; // reduced
    double reference_force_ = 0.0;
    double reference_sum_ = 0.0; // sum of the converged increments' force levels
    long committed_references_ = 0;
    // Tangent predictor: the prescribed DOFs' increments (zero elsewhere) and -K_fp du_p plus
    // the residual at zero increment on the free equations.
    std::vector<double> prescribed_du_;
    std::vector<double> predictor_rhs_; // reduced
    std::vector<double> predicted_du_;  // the tangent predictor's guess, while compared
    std::vector<double> contact_du_;    // the trial increment handed to the contact pairs

    InitialImbalance imbalance_;
    std::vector<TangentCheckRecord> tangent_checks_;
    mutable SolverCounters counters_;
    SolverTimers timers_;
};

} // namespace ifsim::fem
