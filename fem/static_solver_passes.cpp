// StaticSolver: construction, stage set-up, the residual and tangent passes that compose the
// continuum, the stage loads and the contact set, the initial imbalance, and the reports
// (the increment control and Newton are in static_solver.cpp).
#include "fem/static_solver.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "fem/phase_timer.hpp"
#include "fem/vector_norm.hpp"

namespace ifsim::fem {

StaticSolver::StaticSolver(Mesh mesh, std::vector<ElementSetMaterial> materials,
                           SolverSettings settings)
    : mesh_(std::move(mesh)), settings_(std::move(settings)),
      linear_(settings_.linear_solver, settings_.preconditioner_precision) {
    mesh_.validate();
    continuum_ =
        std::make_unique<ContinuumAssembly>(mesh_, std::move(materials), settings_, timers_.k0);
    const auto n_dofs = static_cast<std::size_t>(mesh_.n_nodes() * mesh_.dim());
    u_.assign(n_dofs, 0.0);
    du_.assign(n_dofs, 0.0);
    f_int_.assign(n_dofs, 0.0);
    f_int_committed_.assign(n_dofs, 0.0);
    f_ext_.assign(n_dofs, 0.0);
    f_ext_committed_.assign(n_dofs, 0.0);
}

StaticSolver::~StaticSolver() = default;

const SolverCounters& StaticSolver::counters() const {
    counters_.linear = linear_.counters();
    const ContinuumCounters& m = continuum_->counters();
    counters_.constitutive_evaluations = m.constitutive_evaluations;
    counters_.tangent_evaluations = m.tangent_evaluations;
    counters_.tangent_fallbacks = m.tangent_fallbacks;
    counters_.failed_point_updates = m.failed_point_updates;
    counters_.unreliable_point_updates = m.unreliable_committed;
    counters_.k0_points = m.k0_points;
    counters_.geometry_updates = m.geometry_updates;
    const LoadCounters& l = loads_.counters();
    counters_.gravity_load_builds = l.gravity_load_builds;
    counters_.gravity_load_applications = l.gravity_load_applications;
    counters_.pressure_load_builds = l.pressure_load_builds;
    const ContactSetCounters c = contacts_.counters();
    counters_.contact_pairings = c.pairings;
    counters_.contact_evaluations = c.evaluations;
    counters_.contact_point_updates = c.point_updates;
    counters_.contact_lanes = c.lanes;
    counters_.contact_subincrements = c.subincrements;
    counters_.contact_constitutive_evaluations = c.constitutive_evaluations;
    counters_.contact_model_substeps = c.model_substeps;
    counters_.contact_failures = c.failed_evaluations;
    counters_.contact_relaxed_reruns = c.relaxed_reruns;
    counters_.contact_relaxed_point_updates = c.relaxed_point_updates;
    counters_.contact_viscous_point_updates = c.viscous_point_updates;
    counters_.contact_viscous_share_max = c.viscous_share_max;
    counters_.contact_viscous_traction_max = c.viscous_traction_max;
    counters_.contact_band_clamped = c.band_clamped;
    counters_.contact_dropped_lanes = c.dropped_columns;
    counters_.contact_newton_fallbacks = c.newton_fallbacks;
    return counters_;
}

bool StaticSolver::within_step_budget(std::string& error) {
    if (!budget_active_) { // an evaluation outside a stage's steps (evaluate(), imbalance)
        return true;
    }
    const double spent = contacts_.counters().model_substeps - step_substeps_start_;
    const double points = static_cast<double>(std::max<std::size_t>(1, contacts_.points()));
    if (spent <= settings_.max_step_substeps * points) {
        return true;
    }
    step_over_budget_ = true;
    budget_error_ =
        fmt::format("the interface models needed {:.3g} substeps in this step ({:.3g} per "
                    "contact point), more than the bound of {:.3g} per contact point and "
                    "step ([solver] max_step_substeps); smaller steps, a thicker shear band "
                    "or adaptive sub-increments cost less",
                    spent, spent / points, settings_.max_step_substeps);
    error = budget_error_;
    return false;
}

SolverTimers StaticSolver::timers() const {
    SolverTimers t = timers_;
    t.gravity = loads_.timers().gravity;
    t.pressure = loads_.timers().pressure;
    const ContactPairTimers c = contacts_.timers();
    t.contact_search = c.search;
    t.contact_gather = c.gather;
    t.contact_kernels = c.kernels;
    t.contact_scatter = c.scatter;
    return t;
}

void StaticSolver::add_contact(ContactPairSpec spec) {
    if (stage_count_ > 0) {
        throw std::logic_error("contact pairs are added before the first stage");
    }
    contacts_.add(mesh_, std::move(spec));
}

ElementStresses StaticSolver::stresses(bool trial) const {
    return [this, trial](int e, std::vector<Voigt6>& out) {
        continuum_->element_stresses(e, out, trial);
    };
}

void StaticSolver::begin_contacts(bool dofs_changed) {
    const bool changed = contacts_.begin_increment(mesh_, u_, stresses(false)) || dofs_changed;
    if (!changed && system_) {
        return;
    }
    system_ = std::make_unique<SparseSystem>(mesh_, dofs_, contacts_.couplings());
    ++counters_.patterns_built;
    counters_.contact_pattern_rebuilds += dofs_changed ? 0 : 1;
}

std::vector<double> StaticSolver::state(int element, int point) const {
    return continuum_->state(element, point);
}

std::vector<double> StaticSolver::trial_state(int element, int point) const {
    return continuum_->trial_state(element, point);
}

void StaticSolver::begin_stage(const Stage& stage) {
    DofMap next = build_dof_map(mesh_, stage); // throws before anything changes
    StageLoads::check(mesh_, stage);
    stage_ = stage;
    ++stage_count_;
    const bool dofs_changed = !system_ || next.equation != dofs_.equation;
    dofs_ = std::move(next);
    if (!contacts_.empty()) {
        begin_contacts(dofs_changed);
    } else if (dofs_changed) {
        system_ = std::make_unique<SparseSystem>(mesh_, dofs_);
        ++counters_.patterns_built;
    }
    u_stage_start_ = u_;
    dt_last_ = 0.0;
    loads_.begin(mesh_, stage, u_,
                 stage.gravity ? continuum_->densities(mesh_.n_elements()) : std::vector<double>{});
    residual_.assign(static_cast<std::size_t>(dofs_.n_equations), 0.0);
    correction_.assign(static_cast<std::size_t>(dofs_.n_equations), 0.0);
}

// Residual R = f_ext(t) - f_int(u + du) on the equations: continuum, springs, contact.
bool StaticSolver::residual_pass(double t, std::span<const double> du, std::string& error) {
    if (step_over_budget_) { // no more work in a step past its bound (line search, probes)
        error = budget_error_;
        return false;
    }
    // A failed contact point's record belongs to this pass only: a stage that fails on a
    // material point must not carry an earlier attempt's contact failure as its replay.
    contacts_.forget_failures();
    {
        PhaseTimer timer(timers_.element);
        continuum_->strains(mesh_, du);
        if (!continuum_->update(error)) {
            return false;
        }
    }
    {
        PhaseTimer timer(timers_.assembly);
        continuum_->internal_force(mesh_, *system_, u_, du, f_int_);
        loads_.add_spring_forces(u_, du, f_int_);
    }
    if (!contacts_.empty()) {
        contact_du_.assign(du.begin(), du.end());
        // The bound first: a pass that also failed in Algorithm 1 spent its work too (the
        // costliest passes are the ones that fail on a per-call bound).
        const bool evaluated = contacts_.evaluate(contact_du_, f_int_, error);
        if (!within_step_budget(error) || !evaluated) {
            return false;
        }
    }
    loads_.external_force(t, f_ext_);
    PhaseTimer timer(timers_.assembly);
    std::fill(residual_.begin(), residual_.end(), 0.0);
    for (std::size_t d = 0; d < u_.size(); ++d) {
        const int eq = dofs_.equation[d];
        if (eq >= 0) {
            residual_[static_cast<std::size_t>(eq)] += f_ext_[d] - f_int_[d];
        }
    }
    // The force level of the run: this state's, or the mean over the converged increments
    // (time-averaged, as Abaqus does), so that a body unloaded towards zero stress is not
    // held to a residual relative to its vanishing forces.
    const double averaged = committed_references_ > 0
                                ? reference_sum_ / static_cast<double>(committed_references_)
                                : 0.0;
    reference_force_ =
        std::max({norm2(f_ext_), norm2(f_int_), averaged, settings_.reference_force_floor});
    return true;
}

// Needs the residual pass at the same increment just before (the perturbation lanes start from
// its strain increments and compare with its substep counts).
void StaticSolver::tangent_pass(std::span<const double> du, PrescribedCoupling* coupling) {
    // The tangent depends on the iterate only through what the residual pass left: the
    // material points' trial states and, updated Lagrangian, each point's increment gradient.
    (void)du;
    {
        PhaseTimer timer(timers_.element);
        continuum_->material_tangents(mesh_.dim());
    }
    {
        PhaseTimer timer(timers_.assembly);
        system_->zero_values();
        continuum_->tangent(mesh_, *system_, coupling);
        loads_.add_spring_stiffness(dofs_.equation,
                                    [&](int eq, double k) { system_->add_diagonal(eq, k); });
    }
    contacts_.add_tangent([&](int row, int col, double value) {
        const int r = dofs_.equation[static_cast<std::size_t>(row)];
        const int q = dofs_.equation[static_cast<std::size_t>(col)];
        if (r >= 0 && q >= 0) {
            system_->add_value(r, q, value);
        } else if (coupling != nullptr && r >= 0) {
            coupling->rhs[static_cast<std::size_t>(r)] -=
                value * coupling->prescribed_du[static_cast<std::size_t>(col)];
        }
    });
}

bool StaticSolver::evaluate(double t, std::span<const double> increment, bool with_tangent,
                            std::string& error) {
    if (!stage_) {
        error = "evaluate() before begin_stage()";
        return false;
    }
    if (increment.size() != u_.size()) {
        error = fmt::format("increment of length {} for {} DOFs", increment.size(), u_.size());
        return false;
    }
    try { // updated Lagrangian: the geometry of the committed configuration
        continuum_->begin_increment(mesh_, u_);
    } catch (const std::invalid_argument& e) {
        error = e.what();
        return false;
    }
    if (!residual_pass(t, increment, error)) {
        return false;
    }
    if (with_tangent) {
        tangent_pass(increment);
    }
    return true;
}

void StaticSolver::measure_initial_imbalance() {
    if (!contacts_.empty()) {
        begin_contacts(false);
    }
    std::fill(du_.begin(), du_.end(), 0.0);
    for (std::size_t k = 0; k < dofs_.prescribed.size(); ++k) {
        const auto d = static_cast<std::size_t>(dofs_.prescribed[k]);
        du_[d] = u_stage_start_[d] - u_[d];
    }
    std::string error;
    if (!residual_pass(0.0, du_, error)) {
        return; // the first increment reports the failure
    }
    imbalance_.evaluated = true;
    imbalance_.relative = norm2(residual_) / reference_force_;
    // The largest entry per equation (a tied set's forces sum into its master's equation),
    // named by the first node that carries it.
    double worst = -1.0;
    for (std::size_t d = 0; d < du_.size(); ++d) {
        const int eq = dofs_.equation[d];
        const double r = eq >= 0 ? residual_[static_cast<std::size_t>(eq)] : 0.0;
        if (std::abs(r) > worst) {
            worst = std::abs(r);
            imbalance_.node = static_cast<int>(d) / mesh_.dim();
            imbalance_.direction = static_cast<int>(d) % mesh_.dim();
            imbalance_.force = r;
        }
    }
}

} // namespace ifsim::fem
