#include "io/boundary_value/boundary_value_run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "fem/blas_binding.hpp"
#include "io/boundary_value/boundary_value_effects.hpp"
#include "io/boundary_value/boundary_value_fields.hpp"
#include "io/boundary_value/boundary_value_history.hpp"
#include "io/boundary_value/iteration_log.hpp"
#include "io/boundary_value/tangent_check_file.hpp"
#include "io/output/column_units.hpp"
#include "io/output/history_writer.hpp"
#include "io/output/run_clock.hpp"
#include "io/output/stop_signal.hpp"
#include "io/replay/interface_replay.hpp"

namespace ifsim::io {

namespace {

// Builds the solver and its contact pairs (in the scene's order); throws what fem throws for an
// invalid set-up.
std::unique_ptr<fem::StaticSolver> make_solver(const BoundaryValueScene& scene, bool simd) {
    fem::SolverSettings settings = scene.settings;
    settings.update.simd = simd;
    auto solver = std::make_unique<fem::StaticSolver>(scene.mesh, scene.set_materials(), settings);
    for (const BoundaryValueInterface& c : scene.contacts) {
        fem::ContactPairSpec pair = c.pair;
        pair.options.simd = simd;
        solver->add_contact(std::move(pair));
    }
    return solver;
}

// A pair's keys for summary.json.
nlohmann::ordered_json pair_details(const BoundaryValueInterface& bi) {
    nlohmann::ordered_json j = {{"slave", bi.pair.slave_faces},
                                {"master", bi.pair.master_faces},
                                {"formulation", bi.formulation.name()},
                                {"initial_contact", bi.initial_contact},
                                {"normal_penalty", bi.pair.normal_penalty}};
    if (bi.formulation.is_coulomb()) {
        j["friction_coefficient"] = bi.pair.friction.friction_coefficient;
        j["tangential_stiffness"] = bi.pair.friction.tangential_stiffness;
    } else {
        j["model"] = bi.formulation.material.model;
        j["parameters"] = bi.formulation.material.parameters;
        j["roughness"] = bi.formulation.material.roughness;
        j["shear_band_thickness"] = bi.pair.options.interface.shear_band_thickness;
        j["subincrement"] = bi.formulation.subincrement;
        if (bi.pair.options.interface.adaptive) {
            j["adaptive_partition"] = bi.pair.hold_partition ? "increment" : "iteration";
        }
        j["jacobian"] = bi.formulation.jacobian;
        if (bi.pair.slip_viscosity > 0.0) {
            j["slip_viscosity"] = bi.pair.slip_viscosity;
            j["slip_viscosity_use"] = bi.pair.slip_viscosity_always ? "always" : "retry";
        }
        if (bi.formulation.formulation == InterfaceFormulation::stutz) {
            j["stutz_initial_stress"] = bi.formulation.stutz_initial_stress;
        }
    }
    return j;
}

// Above this relative out-of-balance force the initial state is worth a warning.
constexpr double imbalance_warning = 1.0e-6;

// Once, when the first stage has measured it: an initial state that the supports and loads do
// not hold is almost always a scene mistake (a lateral stress on a free face).
// The contact point whose Algorithm 1 call failed last, if the stage failed on one.
void keep_failed_point(const fem::StaticSolver& solver, const BoundaryValueScene& scene,
                       BoundaryValueRunOutcome& out) {
    for (const auto& pair : solver.contacts()) {
        auto failure = pair->last_failure();
        if (!failure) {
            continue;
        }
        for (std::size_t i = 0; i < scene.contacts.size(); ++i) {
            if (scene.contacts[i].pair.name == pair->spec().name) {
                out.failed_point = std::move(failure);
                out.failed_pair = i;
                return;
            }
        }
    }
}

// The costliest Algorithm 1 call over the pairs (ContactPair::costliest_call): a new record
// is written at once to DIR/costliest-call.toml, so that a run stuck in a hard increment shows
// its costliest call while it runs (a stop signal may end it before its summary).
void keep_costliest_call(const fem::StaticSolver& solver, const BoundaryValueScene& scene,
                         const std::filesystem::path& dir, bool simd,
                         BoundaryValueRunOutcome& out) {
    bool record = false;
    for (const auto& pair : solver.contacts()) {
        auto call = pair->costliest_call();
        if (!call ||
            (out.costliest_call && call->model_substeps <= out.costliest_call->model_substeps)) {
            continue;
        }
        for (std::size_t i = 0; i < scene.contacts.size(); ++i) {
            if (scene.contacts[i].pair.name == pair->spec().name) {
                out.costliest_call = std::move(call);
                out.costliest_pair = i;
                record = true;
                break;
            }
        }
    }
    if (!record) {
        return;
    }
    try {
        write_costliest_call_replay(dir, *out.costliest_call,
                                    scene.contacts[out.costliest_pair].formulation.material, simd);
        out.costliest_call_error.clear();
    } catch (const std::exception& e) {
        out.costliest_call_error = e.what();
    }
}

void warn_initial_imbalance(const fem::StaticSolver& solver, ProgressLine& line, bool& warned) {
    const fem::InitialImbalance& b = solver.initial_imbalance();
    if (warned || !b.evaluated) {
        return;
    }
    warned = true;
    if (b.relative <= imbalance_warning || line.quiet()) {
        return;
    }
    const char* axis[] = {"x", "y", "z"};
    const auto& x = solver.mesh().coordinates;
    const int D = solver.mesh().dim();
    const auto n = static_cast<std::size_t>(b.node * D);
    line.break_line();
    fmt::print(stderr,
               "ifsim: warning: the initial state is not in equilibrium with the first stage's "
               "supports and loads (relative residual {:.2e}; largest at node {} ({:.6g}, "
               "{:.6g}{}) along {}: {:.4g} kN). The first increments will move the body to "
               "equilibrium: support or load the faces whose initial stress is unbalanced.\n",
               b.relative, b.node, x[n], x[n + 1], D == 3 ? fmt::format(", {:.6g}", x[n + 2]) : "",
               axis[b.direction], b.force);
}

} // namespace

BoundaryValueRunOutcome run_boundary_value_scene(const BoundaryValueScene& scene,
                                                 const std::filesystem::path& dir,
                                                 ProgressMode progress, bool simd,
                                                 const BoundaryValueCheckpointing& checkpoints,
                                                 bool iteration_log) {
    BoundaryValueRunOutcome out;
    out.nodes = scene.mesh.n_nodes();
    out.elements = scene.mesh.n_elements();
    const BoundaryValueCheckpoint* resume = checkpoints.resume;
    HistoryWriter history =
        open_history(dir, boundary_value_history_columns(scene), resume ? &resume->run : nullptr);
    CheckpointSchedule checkpoint_due(checkpoints);
    ProgressLine line(progress, scene.total_steps(), static_cast<int>(scene.stages.size()));
    std::unique_ptr<fem::StaticSolver> solver;
    std::optional<FieldOutput> fields; // only when the scene asks: no field code runs otherwise
    std::optional<BoundaryValueProbe> probe;
    std::optional<IterationLog> iterations;
    try {
        const auto t0 = Clock::now();
        solver = make_solver(scene, simd);
        out.setup_seconds = since(t0);
        if (iteration_log) {
            iterations.emplace(dir, resume != nullptr, *solver);
        }
        probe.emplace(scene);
        if (!resume) {
            const auto t1 = Clock::now();
            BoundaryValueRow row;
            probe->initial(*solver, row);
            write_boundary_value_row(history, row);
            out.row_seconds += since(t1);
        }
        if (scene.output.fields.enabled()) {
            fields.emplace(scene, dir);
            out.field_collections = fields->collections();
            out.field_materials = fields->material_names();
            if (resume) {
                fields->restore(resume->fields);
            } else {
                fields->due(0, 0.0, false);
                fields->write(*solver, 0, 0.0);
            }
        }
        long steps_before = resume ? resume->steps_before : 0;
        long increment = resume ? resume->run.increment : 0;
        const std::size_t first_stage = resume ? resume->stage_index : 0;
        if (resume) {
            out.iterations = resume->iterations;
            solver->restore(scene.stages[first_stage], resume->snapshot);
        }
        bool warned = false;
        // The increment a stopped run resumes from (-1: no checkpoint on disk), and how long
        // an increment may go on towards its checkpoint after a stop signal.
        long checkpoint_increment = resume ? resume->run.increment : -1;
        StopPatience increment_patience;
        out.ok = true;
        for (std::size_t k = first_stage; k < scene.stages.size() && out.ok; ++k) {
            const fem::Stage& stage = scene.stages[k];
            const auto on_increment = [&](const fem::IncrementInfo& info) {
                const auto t1 = Clock::now();
                BoundaryValueRow row;
                row.increment = ++increment;
                row.stage = info.stage;
                row.time = static_cast<double>(k) + info.t_end;
                row.newton_iterations = static_cast<int>(info.corrections.size());
                row.cuts = info.cut_depth;
                row.residual = info.residuals.empty() ? 0.0 : info.residuals.back();
                probe->measure(*solver, row);
                write_boundary_value_row(history, row);
                out.iterations.push_back(row.newton_iterations);

                line.update(static_cast<double>(steps_before) + info.t_end * stage.steps,
                            info.stage,
                            fmt::format("increment {}  Newton {}  residual {:.1e}", increment,
                                        row.newton_iterations, row.residual));
                out.row_seconds += since(t1);
                const bool stage_end = info.t_end >= 1.0 - 1.0e-12;
                if (fields && fields->due(increment, row.time, stage_end)) {
                    fields->write(*solver, increment, row.time); // timed by FieldOutput
                }
                // A stop signal makes a checkpoint due at once (the run ends below).
                const bool stop = stop_signal() != 0;
                if (checkpoints.enabled() && (checkpoint_due.due(increment) || stop)) {
                    const auto t2 = Clock::now();
                    BoundaryValueCheckpoint c;
                    c.run = {"boundary-value",
                             checkpoints.scene_text,
                             simd,
                             increment,
                             history.sync(),
                             resume ? resume->run.resumes + 1 : 0,
                             checkpoints.every,
                             checkpoints.minutes};
                    c.stage_index = k;
                    c.cursor = info.next;
                    c.steps_before = steps_before;
                    c.iterations = out.iterations;
                    c.snapshot = solver->snapshot();
                    if (fields) {
                        c.fields = fields->state(); // a resumed run continues the collections
                    }
                    write_boundary_value_checkpoint(dir, c);
                    checkpoint_increment = increment;
                    ++out.checkpoints;
                    checkpoint_due.written();
                    out.checkpoint_seconds += since(t2);
                }
                // `stop` as seen before the checkpoint: a signal arriving since is taken at
                // the next increment, after its checkpoint.
                if (stop) {
                    throw_if_stopped(fmt::format("increment {} (stage {}, time {:.6g})", increment,
                                                 info.stage, row.time),
                                     checkpoints.enabled());
                }
            };
            // A long increment (many Newton iterations, cuts) still moves the line.
            const auto on_iteration = [&](const fem::IncrementInfo& info) {
                // Stopped inside an increment: without checkpoints the run ends at once; with them
                // the increment goes on to its checkpoint (StopWatchdog bounds the wait).
                // An increment that does not end within stop_patience of the signal is given
                // up, so that the run still ends through its own path (summary, tangent
                // checks, the costliest call) before the watchdog's grace runs out; it resumes
                // from the last checkpoint.
                if (!checkpoints.enabled()) {
                    throw_if_stopped(fmt::format("increment {} (during increment {}, Newton "
                                                 "iteration {})",
                                                 increment, increment + 1,
                                                 info.residuals.size() - 1),
                                     false);
                } else if (increment_patience.exhausted()) {
                    const int sig = stop_signal();
                    throw RunInterrupted(
                        sig, fmt::format(
                                 "interrupted by {} after increment {} (increment {} did not end "
                                 "within {} s of the signal: given up at Newton iteration {}){}",
                                 signal_name(sig), increment, increment + 1,
                                 increment_patience.patience().count() / 1000.0,
                                 info.residuals.size() - 1,
                                 checkpoint_increment >= 0
                                     ? fmt::format(" (the last checkpoint is after increment {}: "
                                                   "`ifsim resume DIR` goes on from it)",
                                                   checkpoint_increment)
                                     : std::string(" (no checkpoint written)")));
                }
                warn_initial_imbalance(*solver, line, warned);
                if (iterations) {
                    iterations->record(increment + 1, info, *solver);
                    keep_costliest_call(*solver, scene, dir, simd, out);
                }
                line.update(
                    static_cast<double>(steps_before) + info.t_begin * stage.steps, info.stage,
                    fmt::format("increment {}  Newton {}  residual {:.1e}{}", increment + 1,
                                info.residuals.size() - 1, info.residuals.back(),
                                info.cut_depth > 0 ? fmt::format("  cut x{}", 1 << info.cut_depth)
                                                   : std::string()));
            };
            const fem::StageResult r =
                resume && k == first_stage
                    ? solver->resume_stage(stage, resume->cursor, on_increment, on_iteration)
                    : solver->run_stage(stage, on_increment, on_iteration);
            if (!r.ok) {
                out.ok = false;
                out.reason = r.reason;
                keep_failed_point(*solver, scene, out);
            }
            steps_before += stage.steps;
            if (fields) {
                fields->flush();
            }
        }
    } catch (const RunInterrupted& e) {
        out.ok = false;
        out.reason = e.what();
    } catch (const std::exception& e) {
        // An invalid set-up or a writer error in the middle of the run: keep the rows so far.
        out.ok = false;
        out.reason = fmt::format("run aborted: {}", e.what());
    }
    line.finish();
    if (fields) {
        // Also after a failed run or a writer error: the files written so far are listed.
        try {
            fields->flush();
        } catch (const std::exception& e) {
            out.ok = false;
            out.reason = fmt::format("field output: {}", e.what());
        }
        out.field_outputs = fields->outputs();
        out.field_seconds = fields->seconds();
        out.field_times_unreached = fields->unreached_times();
    }
    if (probe) {
        out.point_recorders = probe->recorders().chosen_points();
    }
    if (solver && iteration_log) { // also after a failed or stopped run: its hard increment
        keep_costliest_call(*solver, scene, dir, simd, out);
    }
    if (solver && scene.settings.check_tangent) {
        try { // also after a failed run: the iterations that led there are the point
            write_tangent_checks(dir, *solver);
        } catch (const std::exception& e) {
            out.ok = false;
            out.reason = e.what();
        }
    }
    if (solver) {
        out.counters = solver->counters();
        out.imbalance = solver->initial_imbalance();
        out.timers = solver->timers();
        out.equations = solver->dof_map().n_equations;
        out.setup_seconds = std::max(0.0, out.setup_seconds - out.timers.k0);
    }
    if (out.ok) {
        remove_checkpoint(dir); // the run is complete: nothing to resume
    }
    const auto t2 = Clock::now();
    history.finish();
    out.finish_seconds = since(t2);
    out.rows = history.rows();
    return out;
}

void add_boundary_value_results(RunSummary& summary, const BoundaryValueScene& scene,
                                const BoundaryValueRunOutcome& run, double parse_s) {
    const fem::SolverCounters& c = run.counters;
    const bool contact = !scene.contacts.empty();
    summary.ok = run.ok;
    summary.reason = run.reason;
    auto& k = summary.counters;
    k["increments"] = c.increments;
    k["newton_iterations"] = c.newton_iterations;
    k["subincrements"] = rounded(c.contact_subincrements);
    k["constitutive_evaluations"] =
        c.constitutive_evaluations + rounded(c.contact_constitutive_evaluations);
    k["cuts"] = c.cuts;
    k["viscous_increments"] = c.viscous_increments;
    k["viscous_holds"] = c.viscous_holds;
    k["viscous_hold_failures"] = c.viscous_hold_failures;
    k["increment_growths"] = c.increment_growths;
    k["predictor_solves"] = c.predictor_solves;
    k["predictor_fallbacks"] = c.predictor_fallbacks;
    k["predictor_rejections"] = c.predictor_rejections;
    k["line_search_steps"] = c.line_search_steps;
    k["stagnation_accepts"] = c.stagnation_accepts;
    k["divergence_cuts"] = c.divergence_cuts;
    k["gathers"] = c.gathers;
    k["partition_solves"] = c.partition_solves;
    k["partition_releases"] = c.partition_releases;
    k["material_evaluations"] = c.constitutive_evaluations;
    k["tangent_evaluations"] = c.tangent_evaluations;
    k["tangent_fallbacks"] = c.tangent_fallbacks;
    k["failed_point_updates"] = c.failed_point_updates;
    if (contact) {
        k["contact_evaluations"] = c.contact_evaluations;
        k["contact_point_updates"] = rounded(c.contact_point_updates);
        k["contact_lanes"] = rounded(c.contact_lanes);
        k["contact_constitutive_evaluations"] = rounded(c.contact_constitutive_evaluations);
        k["contact_model_substeps"] = rounded(c.contact_model_substeps);
        k["contact_pairings"] = c.contact_pairings;
        k["contact_pattern_rebuilds"] = c.contact_pattern_rebuilds;
        k["contact_failures"] = c.contact_failures;
        k["contact_relaxed_reruns"] = c.contact_relaxed_reruns;
        k["contact_relaxed_point_updates"] = rounded(c.contact_relaxed_point_updates);
    }
    if (contact) {
        k["contact_band_clamped"] = c.contact_band_clamped;
        k["contact_dropped_lanes"] = c.contact_dropped_lanes;
        k["contact_newton_fallbacks"] = rounded(c.contact_newton_fallbacks);
        k["contact_viscous_point_updates"] = rounded(c.contact_viscous_point_updates);
        k["contact_viscous_share_max"] = c.contact_viscous_share_max;
        k["contact_viscous_traction_max"] = c.contact_viscous_traction_max;
    }
    k["patterns_built"] = c.patterns_built;
    k["unreliable_point_updates"] = c.unreliable_point_updates;
    if (c.unreliable_point_updates > 0) {
        summary.warnings.push_back(
            {"unreliable_updates", static_cast<double>(c.unreliable_point_updates),
             fmt::format("{} committed material-point update(s) ended on a safeguard (pressure "
                         "floor or tension cut-off): the stress path there is not the model's own",
                         c.unreliable_point_updates)});
    }
    if (c.contact_relaxed_point_updates > 0.0) {
        summary.warnings.push_back(
            {"relaxed_interface_targets", c.contact_relaxed_point_updates,
             fmt::format("{:.0f} committed interface-point update(s) met Eqs. 19-20 only in part "
                         "(in-plane targets relaxed towards t_N where Algorithm 1 could not "
                         "meet the continuum's; docs/fem.md)",
                         c.contact_relaxed_point_updates)});
    }
    if (c.contact_viscous_point_updates > 0.0) {
        summary.warnings.push_back(
            {"slip_viscosity", c.contact_viscous_point_updates,
             fmt::format("{:.0f} committed interface-point update(s) carried a viscous slip "
                         "traction above 1 % of the band's shear (slip_viscosity; largest share "
                         "{:.3g}, largest viscous traction {:.3g} kPa): the response there is "
                         "not the interface model's alone (docs/fem.md)",
                         c.contact_viscous_point_updates, c.contact_viscous_share_max,
                         c.contact_viscous_traction_max)});
    }
    if (c.contact_band_clamped > 0) {
        summary.warnings.push_back(
            {"band_clamped", static_cast<double>(c.contact_band_clamped),
             fmt::format("{} interface-point evaluation(s) ran on a clamped shear band (d_s held "
                         "at min_band_fraction x d_s0): they rest on an assumed thickness",
                         c.contact_band_clamped)});
    }
    k["linear_symbolic_analyses"] = c.linear.symbolic_analyses;
    k["linear_factorisations"] = c.linear.numeric_factorisations;
    k["linear_krylov_solves"] = c.linear.krylov_solves;
    k["linear_krylov_iterations"] = c.linear.krylov_iterations;
    k["linear_krylov_fallbacks"] = c.linear.krylov_fallbacks;
    k["linear_solves"] = c.linear.solves;
    k["k0_points"] = c.k0_points;
    k["geometry_updates"] = c.geometry_updates;
    k["gravity_load_applications"] = c.gravity_load_applications;

    auto& d = summary.details;
    d["effects"] = boundary_value_effects(scene);
    d["mesh"] = {{"dimension", scene.mesh_spec.dimension},
                 {"integration", scene.mesh_spec.integration},
                 {"kinematics", scene.mesh_spec.kinematics},
                 {"bodies", scene.bodies.size()},
                 {"nodes", run.nodes},
                 {"elements", run.elements},
                 {"equations", run.equations}};
    if (!scene.mesh_spec.file.empty()) {
        d["mesh"]["file"] = scene.mesh_spec.path.string();
    }
    double mean = 0.0;
    int max = 0;
    for (int it : run.iterations) {
        mean += it;
        max = std::max(max, it);
    }
    if (!run.iterations.empty()) {
        mean /= static_cast<double>(run.iterations.size());
    }
    d["iterations_per_increment"] = {{"mean", mean}, {"max", max}};
    // Equilibrium reached: the largest relative residual of an accepted increment (at most
    // [solver] residual_tolerance unless an increment stopped at the inner solves' noise floor,
    // counted as stagnation_accepts, at most stagnation_tolerance).
    d["worst_accepted_residual"] = c.worst_accepted_residual;
    // Implicit gather: the largest change of an in-plane target at the last gather of an
    // accepted increment, relative to its size (at most [solver] gather_tolerance).
    d["worst_gather_change"] = c.worst_gather_change;
    if (run.imbalance.evaluated) {
        d["initial_imbalance"] = {{"relative_residual", run.imbalance.relative},
                                  {"node", run.imbalance.node},
                                  {"direction", run.imbalance.direction},
                                  {"force", run.imbalance.force}};
    }
    if (contact) {
        // One pair: "interface" as always; every pair (with its name) under "contacts".
        if (scene.contacts.size() == 1) {
            d["interface"] = pair_details(scene.contacts.front());
        }
        nlohmann::ordered_json pairs = nlohmann::ordered_json::array();
        for (const BoundaryValueInterface& bi : scene.contacts) {
            nlohmann::ordered_json j = {{"name", bi.pair.name}};
            j.update(pair_details(bi));
            pairs.push_back(j);
        }
        d["contacts"] = pairs;
        d["history_contact"] = scene.main_contact()->pair.name;
        d["formulation"] = scene.main_contact()->formulation.name();
    }
    d["linear_solver"] = scene.linear_solver;
    {
        // Where the solve phase goes (seconds are wall time, so not among the counters).
        const fem::BlasBinding blas = fem::blas_binding();
        d["linear_solve_work"] = {{"factorise_s", c.linear.factor_seconds},
                                  {"krylov_s", c.linear.krylov_seconds},
                                  {"factor_copy_s", c.linear.copy_seconds},
                                  {"precondition_s", c.linear.precondition_seconds},
                                  {"factor_flops", c.linear.factor_flops},
                                  {"factor_nonzeros", c.linear.factor_nonzeros},
                                  {"strategy", c.linear.factor_strategy},
                                  {"blas", blas.dgemm_library},
                                  {"blas_threads_pinned", blas.openblas},
                                  {"blas_core", blas.openblas_core}};
        if (!blas.openblas_detected_core.empty()) {
            // OpenBLAS's own choice, replaced because it was its fallback (fem/blas_binding.hpp)
            d["linear_solve_work"]["blas_core_detected"] = blas.openblas_detected_core;
        }
    }
    d["tangent"] = scene.tangent;
    d["predictor"] = scene.predictor;
    d["stages"] = scene.stages.size();
    d["steps"] = scene.total_steps();
    d["rows"] = run.rows;
    d["columns"] = describe_columns("boundary-value", boundary_value_history_columns(scene),
                                    recorder_descriptions(scene.recorders));
    if (!scene.recorders.points.empty()) {
        d["point_recorders"] = run.point_recorders;
    }
    d["outputs"] = {HistoryWriter::file_name};
    if (scene.output.fields.enabled()) {
        const FieldSchedule& f = scene.output.fields;
        for (const std::string& c : run.field_collections) {
            d["outputs"].push_back(c);
        }
        d["fields"] = {{"every", f.every},
                       {"stages", f.stages},
                       {"times", f.times},
                       {"outputs", run.field_outputs},
                       {"collections", run.field_collections},
                       {"materials", run.field_materials},
                       {"times_not_reached", run.field_times_unreached},
                       {"seconds", run.field_seconds}};
    }
    if (!scene.description.empty()) {
        d["description"] = scene.description;
    }
    const fem::SolverTimers& t = run.timers;
    summary.phases = {{"parse", parse_s},
                      {"setup", run.setup_seconds},
                      {"element", t.element},
                      {"assembly", t.assembly},
                      {"solve", t.solve},
                      {"contact_search", t.contact_search},
                      {"contact_gather", t.contact_gather},
                      {"contact_kernels", t.contact_kernels},
                      {"contact_scatter", t.contact_scatter},
                      {"gravity", t.gravity},
                      {"k0", t.k0},
                      {"pressure", t.pressure},
                      {"output", run.row_seconds + run.finish_seconds + run.field_seconds}};
}

} // namespace ifsim::io
