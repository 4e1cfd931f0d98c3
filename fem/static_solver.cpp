// StaticSolver: the increment control, the first guess and Newton (the passes that evaluate
// residual and tangent, the stage set-up and the reports are in static_solver_passes.cpp).
#include "fem/static_solver.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "fem/newton_divergence.hpp"
#include "fem/phase_timer.hpp"
#include "fem/vector_norm.hpp"

namespace ifsim::fem {
namespace {

// The last relative residuals of a Newton iteration, for a failure message.
std::string residual_trace(const std::vector<double>& residuals) {
    const std::size_t n = residuals.size();
    const std::size_t from = n > 8 ? n - 8 : 0;
    std::string out = from > 0 ? "... " : "";
    for (std::size_t i = from; i < n; ++i) {
        out += fmt::format("{}{:.1e}", i > from ? " " : "", residuals[i]);
    }
    return out;
}

} // namespace

// One increment: first guess, then Newton until converged (or at the inner solves' noise
// floor) with the in-plane targets settled. Nothing is committed here.
bool StaticSolver::solve_increment(double t_begin, double t_end, IncrementInfo& info,
                                   std::string& error, const IncrementCallback& on_iteration) {
    try { // updated Lagrangian: the geometry of the converged configuration
        continuum_->begin_increment(mesh_, u_);
    } catch (const std::invalid_argument& e) {
        error = e.what();
        return false;
    }
    if (!contacts_.empty()) {
        begin_contacts(false);
        // The slip viscosity's time: the increment's share of its nominal step (exact: every
        // increment of a step is 1 / 2^depth of it).
        contacts_.set_increment_length(std::ldexp(1.0, -info.cut_depth));
    }
    // Reused factorisations live within one increment: a run resumed from a checkpoint
    // (which holds none) then takes the uninterrupted run's path bit for bit.
    factorisation_stale_ = true;
    bool residual_current = false;
    first_guess(t_begin, t_end, residual_current);
    if (!residual_current && !residual_pass(t_end, du_, error)) {
        return false;
    }
    const double tol_r = settings_.residual_tolerance;
    const double tol_u = settings_.displacement_tolerance;
    double last_correction = std::numeric_limits<double>::infinity();
    double rel = norm2(residual_) / reference_force_;
    // Each re-gather of the in-plane targets starts a new Newton solve from the converged
    // iterate: the iteration budget is per solve (a budget shared with the gathers ended
    // increments that had converged to 1e-10 twice and were restarted by a gather).
    int solve_start = 0;
    bool early_gathered = false; // this solve's early gather done
    // New targets or sub-increments: the residual of the same displacements with them starts
    // another solve after iteration it.
    const auto restart_solve = [&](int it) {
        if (!residual_pass(t_end, du_, error)) {
            return false;
        }
        rel = norm2(residual_) / reference_force_;
        last_correction = std::numeric_limits<double>::infinity();
        solve_start = it + 1;
        early_gathered = false;
        return true;
    };
    for (int it = 0;; ++it) {
        // The contacts' last evaluation is this iterate's: their sub-increment choices hold.
        contacts_.hold_chosen_partitions();
        info.residuals.push_back(rel);
        if (on_iteration) {
            on_iteration(info);
        }
        if (!std::isfinite(rel)) {
            error = "the residual is not finite";
            return false;
        }
        // Converged, or at the noise floor of the inner solves (small and no longer falling).
        const auto& r = info.residuals;
        const bool converged =
            rel <= 1.0e-2 * tol_r || (it > 0 && rel <= tol_r && last_correction <= tol_u);
        const bool stagnated = !converged && settings_.stagnation_tolerance > 0.0 &&
                               it - solve_start >= 3 && rel <= settings_.stagnation_tolerance &&
                               rel > 0.5 * r[r.size() - 4];
        // Early gather (SolverSettings::early_gather_residual): targets that would move are
        // gathered before the last digits are converged with them.
        if (!converged && !stagnated && !early_gathered && it > solve_start &&
            rel <= settings_.early_gather_residual) {
            early_gathered = true;
            error.clear();
            if (!targets_settled(info, error, true)) {
                if (!error.empty() || !restart_solve(it)) {
                    return false;
                }
                continue;
            }
        }
        if (converged || stagnated) {
            // A line-search trial that failed before a smaller step succeeded left its message
            // in error: only targets_settled may speak now.
            error.clear();
            const bool settled = targets_settled(info, error);
            if (!error.empty()) {
                return false; // the targets did not settle in max_gathers
            }
            if (!settled || partitions_released(info)) {
                if (!restart_solve(it)) {
                    return false;
                }
                continue;
            }
            if (stagnated) {
                info.stagnated = true;
                ++counters_.stagnation_accepts;
            }
            return true;
        }
        if (settings_.divergence_check &&
            newton_diverged(info.residuals, static_cast<std::size_t>(solve_start))) {
            ++counters_.divergence_cuts;
            error = fmt::format("Newton diverged: after {} iterations the relative residual "
                                "{:.3e} is above the {:.3e} it started from (residuals {}); cut "
                                "early",
                                it - solve_start, rel,
                                info.residuals[static_cast<std::size_t>(solve_start)],
                                residual_trace(info.residuals));
            return false;
        }
        if (it - solve_start == settings_.max_iterations) {
            error = fmt::format(
                "Newton did not converge in {} iterations{} (relative residual "
                "{:.3e}, last relative correction {:.3e}; residuals {})",
                settings_.max_iterations,
                info.gathers > 0
                    ? fmt::format(" after {} re-gathers of the in-plane targets", info.gathers)
                    : std::string(),
                rel, last_correction, residual_trace(info.residuals));
            return false;
        }
        if (!newton_step(t_end, rel, last_correction, info, error)) {
            return false;
        }
    }
}

// The residual at the guess is left current (residual_current) when the guess was the last
// evaluation, so the increment does not evaluate it again.
void StaticSolver::first_guess(double t_begin, double t_end, bool& residual_current) {
    residual_current = false;
    std::fill(du_.begin(), du_.end(), 0.0);
    for (std::size_t k = 0; k < dofs_.prescribed.size(); ++k) {
        const auto d = static_cast<std::size_t>(dofs_.prescribed[k]);
        du_[d] = u_stage_start_[d] + dofs_.prescribed_change[k] * t_end - u_[d];
    }
    const Predictor predictor = settings_.predictor;
    if (predictor == Predictor::extrapolated && dt_last_ > 0.0) {
        const double scale = (t_end - t_begin) / dt_last_;
        for (std::size_t d = 0; d < du_.size(); ++d) {
            if (dofs_.equation[d] >= 0) {
                du_[d] = scale * du_last_[d];
            }
        }
        return;
    }
    if (predictor == Predictor::zero) {
        return;
    }
    // The predictor's evaluations are probes: a contact point that fails in one of them must
    // not relax its targets for the increment that follows.
    contacts_.set_probing(true);
    std::string why_not;
    const bool predicted = tangent_predictor(t_end, why_not);
    if (!predicted) {
        contacts_.set_probing(false);
        // A singular tangent at the committed state (e.g. a contact just touching) or a point
        // that fails there: no guess; the increment's own evaluation reports real failures.
        zero_free_dofs();
        ++counters_.predictor_fallbacks;
        return;
    }
    if (predictor == Predictor::extrapolated) {
        // The linearisation can be far off over a strongly non-linear step (a coarse shear
        // increment: the interface predicted to stick drags the soil 6 mm): keep the zero
        // guess when its residual is smaller. Both residuals carry the same external force,
        // so their norms compare directly.
        std::string unused;
        predicted_du_.assign(du_.begin(), du_.end());
        zero_free_dofs();
        const double zero_norm = residual_pass(t_end, du_, unused)
                                     ? norm2(residual_)
                                     : std::numeric_limits<double>::infinity();
        du_.assign(predicted_du_.begin(), predicted_du_.end());
        const bool evaluated = residual_pass(t_end, du_, unused);
        const double tangent_norm =
            evaluated ? norm2(residual_) : std::numeric_limits<double>::infinity();
        if (tangent_norm <= zero_norm) {
            residual_current = evaluated;
        } else {
            zero_free_dofs();
            ++counters_.predictor_rejections;
        }
    }
    contacts_.set_probing(false);
}

void StaticSolver::zero_free_dofs() {
    for (std::size_t d = 0; d < du_.size(); ++d) {
        du_[d] = dofs_.equation[d] >= 0 ? 0.0 : prescribed_du_[d];
    }
}

// Linearised at the committed state: K_ff du_f = R(u_n, t_end) - K_fp du_p. The residual at
// du = 0 carries the load change of the increment, the product with K_fp the prescribed
// motion; both through the tangent of the state every point is known to be in.
bool StaticSolver::tangent_predictor(double t_end, std::string& error) {
    prescribed_du_.assign(du_.begin(), du_.end());
    std::fill(du_.begin(), du_.end(), 0.0);
    if (!residual_pass(t_end, du_, error)) {
        return false;
    }
    predictor_rhs_.assign(residual_.begin(), residual_.end());
    PrescribedCoupling coupling{prescribed_du_, predictor_rhs_};
    tangent_pass(du_, &coupling);
    {
        PhaseTimer timer(timers_.solve);
        if (!solve_tangent_system(predictor_rhs_.data(), correction_.data(),
                                  settings_.krylov_tolerance, error)) {
            return false;
        }
    }
    ++counters_.predictor_solves;
    for (std::size_t d = 0; d < du_.size(); ++d) {
        const int eq = dofs_.equation[d];
        du_[d] = eq >= 0 ? correction_[static_cast<std::size_t>(eq)] : prescribed_du_[d];
    }
    return true;
}

bool StaticSolver::solve_tangent_system(const double* b, double* x, double forcing,
                                        std::string& error) {
    const double rtol = std::max(1.0e-12, std::min(settings_.krylov_tolerance, forcing));
    if (settings_.reuse_factorisation && !factorisation_stale_ &&
        linear_.holds_factorisation(system_->pattern_id())) {
        const long before = linear_.counters().krylov_iterations;
        const bool converged = linear_.solve_preconditioned(system_->matrix(), b, x, rtol,
                                                            settings_.krylov_max_iterations);
        const long steps = linear_.counters().krylov_iterations - before;
        krylov_steps_since_factorisation_ += steps;
        ++solves_since_factorisation_;
        if (converged) {
            // Keep the factorisation while a solve with it costs no more than the mean cost
            // per solve since it was made, its own cost shared out (the factorisation's
            // direct solve counts as one): beyond that a new one is cheaper on average.
            const double mean = (settings_.krylov_factorisation_cost +
                                 static_cast<double>(krylov_steps_since_factorisation_)) /
                                static_cast<double>(solves_since_factorisation_ + 1);
            factorisation_stale_ = static_cast<double>(steps) > mean;
            return true;
        }
    }
    krylov_steps_since_factorisation_ = 0;
    solves_since_factorisation_ = 0;
    factorisation_stale_ = false;
    return linear_.factorise(system_->matrix(), system_->pattern_id(), error) &&
           linear_.solve(b, x, error);
}

bool StaticSolver::newton_step(double t_end, double& rel, double& correction, IncrementInfo& info,
                               std::string& error) {
    tangent_pass(du_);
    {
        PhaseTimer timer(timers_.solve);
        if (!solve_tangent_system(residual_.data(), correction_.data(), rel, error)) {
            return false;
        }
    }
    ++counters_.newton_iterations;
    if (settings_.check_tangent) {
        check_tangent(t_end, info);
    }
    // Backtracking line search on the residual norm: halve the step while the residual
    // grows (a kink of the response sends full Newton steps into 2-cycles). A failed
    // evaluation (a material or interface point) is also retried with half the step.
    du_start_.assign(du_.begin(), du_.end());
    double alpha = 1.0;
    double rel_new = 0.0;
    for (int ls = 0;; ++ls) {
        for (std::size_t d = 0; d < du_.size(); ++d) {
            const int eq = dofs_.equation[d];
            du_[d] = eq >= 0 ? du_start_[d] + alpha * correction_[static_cast<std::size_t>(eq)]
                             : du_start_[d];
        }
        const bool evaluated = residual_pass(t_end, du_, error);
        rel_new = evaluated ? norm2(residual_) / reference_force_
                            : std::numeric_limits<double>::infinity();
        const bool worse = !(rel_new <= rel) && rel_new > settings_.residual_tolerance;
        // A failed evaluation may halve further: near a stress-free state the soil's
        // tangent is almost singular and the full step lands far outside what the
        // interface (or a material point) can follow.
        const int limit =
            evaluated ? settings_.max_line_search : std::max(settings_.max_line_search, 12);
        if (!worse || ls >= limit) {
            if (!evaluated) {
                return false;
            }
            break;
        }
        alpha *= 0.5;
        ++info.line_search_steps;
        ++counters_.line_search_steps;
    }
    correction = alpha * norm2(correction_) / std::max(norm2(du_), 1.0e-300);
    info.corrections.push_back(correction);
    rel = rel_new;
    return true;
}

bool StaticSolver::partitions_released(IncrementInfo& info) {
    if (contacts_.empty() || info.partition_solves >= max_partition_solves) {
        return false;
    }
    const std::size_t released = contacts_.release_outgrown_partitions();
    if (released == 0) {
        return false;
    }
    ++info.partition_solves;
    ++counters_.partition_solves;
    counters_.partition_releases += static_cast<long>(released);
    return true;
}

bool StaticSolver::targets_settled(IncrementInfo& info, std::string& error, bool probe) {
    if (contacts_.empty() || settings_.max_gathers <= 0) {
        return true;
    }
    const double change = contacts_.regather(stresses(true));
    if (change <= settings_.gather_tolerance) {
        if (probe) {
            contacts_.restore_targets(); // the solve goes on undisturbed
            return true;
        }
        info.gather_change = change;
        counters_.worst_gather_change = std::max(counters_.worst_gather_change, change);
        return true;
    }
    if (probe && info.gathers >= settings_.max_gathers) {
        // Out of gathers: the probe's unconverged iterate must not cut the increment; the
        // gather at convergence decides, as without the probe.
        contacts_.restore_targets();
        return true;
    }
    info.gather_change = change;
    if (info.gathers >= settings_.max_gathers) {
        error = fmt::format("the in-plane stresses gathered from the continuum (Eqs. 14-16) did "
                            "not settle in {} gathers (last change {:.2e} of their size)",
                            settings_.max_gathers, change);
        return false;
    }
    ++info.gathers;
    ++counters_.gathers;
    if (settings_.gather_aitken) {
        contacts_.relax_targets();
    }
    return false;
}

void StaticSolver::commit_increment(double dt) {
    continuum_->commit();
    contacts_.commit();
    for (std::size_t d = 0; d < u_.size(); ++d) {
        u_[d] += du_[d];
    }
    f_int_committed_ = f_int_;
    reference_sum_ += std::max(norm2(f_ext_), norm2(f_int_));
    ++committed_references_;
    du_last_ = du_;
    dt_last_ = dt;
    f_ext_committed_ = f_ext_;
    ++counters_.increments;
}

StageResult StaticSolver::run_stage(const Stage& stage, const IncrementCallback& on_increment,
                                    const IncrementCallback& on_iteration) {
    begin_stage(stage);
    if (stage_count_ == 1) {
        measure_initial_imbalance();
    }
    return stage_from(stage, StageCursor{}, on_increment, on_iteration);
}

StageResult StaticSolver::resume_stage(const Stage& stage, const StageCursor& from,
                                       const IncrementCallback& on_increment,
                                       const IncrementCallback& on_iteration) {
    return stage_from(stage, from, on_increment, on_iteration);
}

StageResult StaticSolver::stage_from(const Stage& stage, StageCursor from,
                                     const IncrementCallback& on_increment,
                                     const IncrementCallback& on_iteration) {
    StageResult result;
    const int steps = std::max(1, stage.steps);
    const int max_cuts = std::max(0, settings_.max_cuts);
    // The step work bound applies inside the steps only, and ends with them.
    struct BudgetOff {
        StaticSolver& s;
        ~BudgetOff() {
            s.budget_active_ = s.step_over_budget_ = false;
            s.contacts_.set_viscous_retry(false);
        }
    } budget_off{*this};
    bool viscous_retry = false; // the increment is solved with the slip viscosity
    bool viscous_held = false;  // ... without having failed first (hold_slip_viscosity)
    bool held_failed = false;   // this increment failed held and is solved without it
    const auto set_viscous = [&](bool on, bool held) {
        viscous_retry = on;
        viscous_held = held;
        contacts_.set_viscous_retry(on);
        if (on) {
            dt_last_ = 0.0; // the retry's first guess, also when held: the same solve
        }
    };
    int next_start_depth = 0; // carry_cuts: where the next step starts
    int calm_steps = from.calm_steps;
    for (int k = std::max(1, from.step); k <= steps; ++k) {
        // Automatic increment control inside the nominal step [t_a, t_step]: the increment is
        // halved on failure (up to max_cuts times) and doubled again after growth_after
        // converged increments in a row, never past the step's end, so a hard stretch costs
        // small increments only while it lasts.
        const bool resumed = k == from.step;
        double t_a = resumed ? from.t_a : double(k - 1) / steps;
        const double t_step = double(k) / steps;
        int depth = resumed ? from.depth : next_start_depth;
        const int start_depth = resumed ? from.start_depth : depth;
        int streak = resumed ? from.streak : 0;
        // A resume may have changed the settings (ifsim resume --set): hold only where this
        // run would have held.
        if (resumed && from.viscous_held && settings_.hold_slip_viscosity && depth >= max_cuts &&
            contacts_.viscous_fallback()) {
            set_viscous(true, true);
        }
        step_substeps_start_ =
            contacts_.counters().model_substeps - (resumed ? from.step_substeps : 0.0);
        step_over_budget_ = false;
        budget_active_ = true;
        while (true) {
            const double h = 1.0 / (double(steps) * std::ldexp(1.0, depth));
            const bool last = t_a + h >= t_step - 1.0e-12 * h;
            const double t_b = last ? t_step : t_a + h;
            IncrementInfo info;
            info.stage = stage_count_;
            info.step = k;
            info.t_begin = t_a;
            info.t_end = t_b;
            info.cut_depth = depth;
            std::string error;
            if (solve_increment(t_a, t_b, info, error, on_iteration)) {
                commit_increment(t_b - t_a);
                held_failed = false;
                const bool was_viscous = viscous_retry;
                if (viscous_retry) {
                    ++counters_.viscous_increments;
                    counters_.viscous_holds += viscous_held ? 1 : 0;
                    set_viscous(false, false);
                }
                ++result.increments;
                counters_.worst_accepted_residual =
                    std::max(counters_.worst_accepted_residual, info.residuals.back());
                t_a = t_b;
                if (!last && depth > 0 && ++streak >= settings_.growth_after) {
                    // Grow back only to a size that divides the rest of the step evenly.
                    const double rest = (t_step - t_a) * double(steps) * std::ldexp(1.0, depth);
                    if (std::fmod(std::round(rest), 2.0) == 0.0) {
                        --depth;
                        streak = 0;
                        ++counters_.increment_growths;
                    }
                }
                // Held: the next increment, still at the finest cut of this step, takes the
                // viscosity at once (SolverSettings::hold_slip_viscosity).
                const bool hold =
                    was_viscous && settings_.hold_slip_viscosity && !last && depth >= max_cuts;
                if (hold) {
                    set_viscous(true, true);
                }
                if (last && settings_.carry_cuts > 0) {
                    // The next step starts where this one ended; a calm run of steps grows it.
                    calm_steps = depth <= start_depth ? calm_steps + 1 : 0;
                    next_start_depth = depth;
                    if (calm_steps >= settings_.carry_cuts && next_start_depth > 0) {
                        --next_start_depth;
                        calm_steps = 0;
                    }
                }
                info.next =
                    last ? StageCursor{k + 1, t_step, next_start_depth, 0,
                                       0.0,   false,  next_start_depth, calm_steps}
                         : StageCursor{k,
                                       t_a,
                                       depth,
                                       streak,
                                       contacts_.counters().model_substeps - step_substeps_start_,
                                       hold,
                                       start_depth,
                                       calm_steps};
                if (on_increment) {
                    on_increment(info);
                }
                if (last) {
                    break;
                }
                continue;
            }
            if (step_over_budget_) {
                result.ok = false;
                result.reason = fmt::format("stage {} ('{}'), step {} of {}, pseudo-time {:.6g} to "
                                            "{:.6g}: {}",
                                            stage_count_, stage.name, k, steps, t_a, t_b, error);
                return result;
            }
            if (depth >= max_cuts && viscous_held) {
                // Held, and no equilibrium with the viscosity: the band may have found its own
                // again. Once more without it, where the retrying run would have started.
                ++counters_.viscous_hold_failures;
                set_viscous(false, false);
                held_failed = true;
                continue;
            }
            if (depth >= max_cuts && !viscous_retry && !held_failed &&
                contacts_.viscous_fallback()) {
                // No equilibrium near the last one even at the finest increment: a band past
                // its peak under load control (docs/fem.md, "Slip viscosity"). Once more with
                // the pairs' slip viscosity, for this increment only.
                set_viscous(true, false);
                continue;
            }
            if (depth >= max_cuts) {
                result.ok = false;
                result.reason = fmt::format(
                    "stage {} ('{}'), step {} of {}, pseudo-time {:.6g} to {:.6g}: {} (after "
                    "halving the step {} times{})",
                    stage_count_, stage.name, k, steps, t_a, t_b, error, depth,
                    held_failed     ? ", with the slip viscosity held from the increment before "
                                      "and then without it"
                    : viscous_retry ? ", the last time with the slip viscosity"
                                    : "");
                return result;
            }
            ++counters_.cuts;
            dt_last_ =
                0.0; // no extrapolation for the retry: it may have misled (tangent predictor)
            ++depth;
            streak = 0;
        }
    }
    return result;
}

} // namespace ifsim::fem
