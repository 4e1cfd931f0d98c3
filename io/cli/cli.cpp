#include "io/cli/cli.hpp"

#include <exception>
#include <filesystem>
#include <iostream>
#include <stdexcept>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "io/calibrate/calibrate_command.hpp"
#include "io/cli/exit_codes.hpp"
#include "io/cli/kernel_bench.hpp"
#include "io/cli/run_command.hpp"
#include "io/output/summary_writer.hpp"
#include "io/sweep/sweep_command.hpp"

namespace ifsim::io {

namespace {

constexpr const char* app_footer = R"(
  ifsim run SCENE.toml --out DIR [--set KEY=VALUE]... [--threads N] [--scalar]
  ifsim sweep SWEEP.toml --out DIR [--jobs N] [--threads-per-run T] [--list]
  ifsim calibrate CAL.toml --out DIR [--jobs N]
  ifsim kernel-bench --model MODEL [--formulation F] --points N [--threads T] [--scalar]
                     [--seconds S] [--jacobian J] [--subincrement fixed|adaptive]
Scene kinds: element-test (one material point), interface-test (simple interface shear:
a sample in series with one interface point, paper section 5), boundary-value (finite
elements: structured 2D/3D bodies or a Gmsh .msh mesh, contact pairs with their interface
formulations, stages of prescribed displacements, ties, pressures, springs and gravity).
Units kPa and m; compression negative; Voigt order 11 22 33 12 13 23 with tensor shear
strains. Scene schema: docs/scenes.md; example scenes: scenes/. `ifsim run --help` and
`ifsim kernel-bench --help` explain each command.)";

constexpr const char* run_footer = R"(
Scene keys, --set syntax, outputs and exit codes: docs/scenes.md.
  --set KEY=VALUE   KEY is a dotted path; numbers pick array entries counted from 1
                    (stage.2.deps_11 = deps_11 of the second [[stage]]); VALUE is a TOML
                    value (0.5, "text", [1, 2], true) or a bare word taken as a string.
Outputs in DIR: history.csv (one row per step or, for boundary-value scenes, per converged
increment; row 0 = initial state) and, last,
summary.json (status, timing, counters), written atomically.
Exit codes: 0 ok, 1 output could not be written, 2 bad command line or scene, 3 run failed.)";

constexpr const char* sweep_footer = R"(
A sweep file names a base scene and lists of values for scene keys (the --set keys):
  scene = "simple-shear-cnl-stutz.toml"   # or a list of scenes; relative to the sweep file
  [grid]                                  # every combination, the last key fastest
  "interface.roughness" = [0.8, 0.9, 1.0]
  "interface.shear_band_thickness" = [0.002, 0.003]
  [zip]                                   # optional: the n-th values together
  [set]                                   # optional: overrides for every run
  "interface.subincrement" = "adaptive"
Each run is `ifsim run` into DIR/runs/<id>/ (id = hash of the scene file's text and the
overrides; its console output in run.log). DIR/sweep.csv: one row per run in sweep order
(swept values, status, reason, wall_s, the summary's results and counters); DIR/sweep.json:
counts and status. Running the same command again skips runs whose summary says ok and redoes
failed or killed ones. Exit codes: 0 all ok, 2 bad sweep file, 3 a run failed, 1 DIR not
writable, 128+N stopped by signal N (the table is then sweep.csv.partial).
Across ranks and machines: mpirun -np N ifsim sweep ... (Open MPI; --jobs is then per rank,
DIR on a file system every rank sees). Overlay plot of all runs: scripts/plot_sweep.py DIR.
Docs: docs/sweeps.md.)";

constexpr const char* calibrate_footer = R"(
A calibration file names a scene, a measured curve and the keys to fit:
  scene = "../scenes/simple-shear-cnl-stutz.toml"   # relative to the calibration file
  data = "measured.csv"        # CSV with columns u_t (m), t_t (kPa) and optionally u_n (m)
  [parameters]
  "interface.roughness" = { initial = 0.8, bounds = [0.5, 0.95] }
  "interface.shear_band_thickness" = { initial = 0.002, bounds = [0.001, 0.006] }
  [set]                        # optional: overrides of every run
  [fit]                        # optional: weight_u_n = 1.0, max_iterations = 30, step = 0.01
  [columns]                    # optional: the data file's column names (u_t, t_t, u_n)
Least squares (Ceres Solver, Levenberg-Marquardt within the bounds) of (run - data) / scale at
every data point, run and data compared at equal path length of u_t. Each Jacobian is n + 1
runs at once over the cores (and MPI ranks under mpirun). Outputs in DIR: calibration.json
(fitted values, cost, rms residuals, convergence), fit.csv, evaluations.csv, runs/<id>/.
Plot: scripts/plot_calibration.py DIR. Docs: docs/calibration.md.)";

constexpr const char* bench_footer = R"(
Prints one JSON object: model, formulation, points, threads, path (simd | scalar),
evaluations_per_second (constitutive evaluations, perturbed lanes included),
points_per_second (complete point updates; for an interface formulation the whole
Algorithm 1 with its Jacobian columns), and details (lanes, updates, wall_s, ...; for an
interface formulation lanes_per_point and subincrements_per_point). The states are never
committed: every repetition integrates the same valid states with the same increments.
--formulation novel | stutz times the contact engine with --model hypoplasticity | sanisand
as interface model; --formulation coulomb times batched Coulomb friction (no continuum model:
--model coulomb, or any model name, which is then not used).)";

} // namespace

namespace {

// --checkpoint-every and --checkpoint-minutes, the same for `run` and `resume`.
void add_checkpoint_options(CLI::App* cmd, RunOptions& opt) {
    cmd->add_option("--checkpoint-every", opt.checkpoint_every,
                    "Write DIR/checkpoint every N increments or steps (continue a killed run "
                    "with `ifsim resume DIR`; every scene kind)")
        ->check(CLI::Range(1L, 1'000'000'000L));
    cmd->add_option("--checkpoint-minutes", opt.checkpoint_minutes,
                    "Write DIR/checkpoint every M minutes of wall-clock time")
        ->check(CLI::PositiveNumber);
}

// --iteration-log, the same for `run` and `resume` (a resumed run appends).
void add_iteration_log_flag(CLI::App* cmd, RunOptions& opt) {
    cmd->add_flag("--iteration-log", opt.iteration_log,
                  "Boundary-value scenes: write DIR/iterations.csv, one row per Newton iteration "
                  "with its time and contact counters (where a hard increment spends its time)");
}

} // namespace

int run_cli(int argc, const char* const* argv) {
    CLI::App app{fmt::format("ifsim {} ({}): continuum soil models as interface models "
                             "(Staubach, Machacek, Wichtmann 2022)",
                             build_version(), build_revision()),
                 "ifsim"};
    app.require_subcommand(1);
    app.footer(app_footer);
    app.set_version_flag("--version",
                         fmt::format("ifsim {} ({})", build_version(), build_revision()));

    RunOptions run;
    bool progress = false;
    CLI::App* run_cmd = app.add_subcommand("run", "Run a scene and write its results into DIR");
    run_cmd->add_option("scene", run.scene, "Scene file (TOML)")->required();
    run_cmd->add_option("--out,-o", run.out, "Output directory (created if missing)")->required();
    run_cmd->add_option("--set", run.sets, "Override a scene key: KEY=VALUE (repeatable)")
        ->type_name("KEY=VALUE")
        ->allow_extra_args(false);
    run_cmd->add_option("--threads", run.threads, "Worker threads (default: all cores)")
        ->check(CLI::Range(1, 4096));
    run_cmd->add_flag("--replace", run.replace,
                      "Remove an earlier run's outputs in DIR (default: move them to "
                      "DIR/previous-<UTC time>/)");
    run_cmd->add_flag("--fields", run.fields,
                      "Boundary-value scenes: write VTU fields at the end of every stage "
                      "(with the scene's [output] fields)");
    run_cmd
        ->add_option("--fields-every", run.fields_every,
                     "Boundary-value scenes: write VTU fields every N increments")
        ->check(CLI::Range(1L, 1'000'000'000L));
    add_checkpoint_options(run_cmd, run);
    add_iteration_log_flag(run_cmd, run);
    run_cmd->add_flag("--scalar", run.scalar,
                      "Use the scalar kernel path instead of SIMD (same results to round-off)");
    auto* progress_flag = run_cmd->add_flag(
        "--progress", progress, "Show the progress line even when stderr is not a terminal");
    run_cmd->add_flag("--quiet,-q", run.quiet, "No progress line and no result line")
        ->excludes(progress_flag);
    run_cmd->footer(run_footer);

    RunOptions resume;
    resume.resume = true;
    std::string resume_dir;
    bool resume_progress = false;
    CLI::App* resume_cmd = app.add_subcommand(
        "resume", "Continue a killed or stopped run from DIR/checkpoint (every scene kind)");
    resume_cmd->add_option("dir", resume_dir, "The run's output directory")->required();
    resume_cmd->add_option("--threads", resume.threads, "Worker threads (default: all cores)")
        ->check(CLI::Range(1, 4096));
    resume_cmd
        ->add_option("--set", resume.sets,
                     "Boundary-value runs: change how the equations are solved from the "
                     "checkpoint on, KEY=VALUE (repeatable; solver.* and a pair's solution "
                     "controls, e.g. contact.1.jacobian); noted in DIR/scene.toml")
        ->type_name("KEY=VALUE")
        ->allow_extra_args(false);
    add_checkpoint_options(resume_cmd, resume);
    add_iteration_log_flag(resume_cmd, resume);
    auto* resume_progress_flag = resume_cmd->add_flag(
        "--progress", resume_progress, "Show the progress line even when stderr is not a terminal");
    resume_cmd->add_flag("--quiet,-q", resume.quiet, "No progress line and no result line")
        ->excludes(resume_progress_flag);
    resume_cmd->footer("The run goes on from its last checkpoint with the scene DIR/scene.toml "
                       "and the kernel path it started with; rows after the checkpoint are "
                       "written again, so history.csv ends as the uninterrupted run's (not "
                       "with --set, which changes the run from the checkpoint on).");

    SweepOptions sweep;
    CLI::App* sweep_cmd = app.add_subcommand(
        "sweep", "Run a scene over a grid of key values, a queue over the cores (sweep.csv)");
    sweep_cmd->add_option("sweep", sweep.sweep_file, "Sweep file (TOML)")->required();
    auto* sweep_out =
        sweep_cmd->add_option("--out,-o", sweep.out, "Output directory (created if missing)");
    sweep_cmd
        ->add_option("--jobs,-j", sweep.jobs,
                     "Runs at a time (default: one per core; under mpirun: per rank, default 1)")
        ->check(CLI::Range(1, 4096));
    sweep_cmd
        ->add_option("--threads-per-run", sweep.threads_per_run,
                     "Worker threads of each run (default: the cores shared out between the "
                     "runs at a time)")
        ->check(CLI::Range(1, 4096));
    sweep_cmd->add_flag("--scalar", sweep.scalar, "Every run on the scalar kernel path");
    sweep_cmd->add_flag("--quiet,-q", sweep.quiet, "No line per finished run");
    auto* sweep_list = sweep_cmd->add_flag(
        "--list", sweep.list, "Print the runs (number, id, scene, overrides); run nothing");
    sweep_out->excludes(sweep_list);
    sweep_cmd->footer(sweep_footer);

    CalibrateOptions calibrate;
    CLI::App* calibrate_cmd = app.add_subcommand(
        "calibrate", "Fit scene keys (roughness, band thickness, ...) to a measured curve");
    calibrate_cmd->add_option("calibration", calibrate.file, "Calibration file (TOML)")->required();
    calibrate_cmd->add_option("--out,-o", calibrate.runs.out, "Output directory")->required();
    calibrate_cmd
        ->add_option("--jobs,-j", calibrate.runs.jobs,
                     "Runs at a time (default: one per core; under mpirun: per rank, default 1)")
        ->check(CLI::Range(1, 4096));
    calibrate_cmd
        ->add_option("--threads-per-run", calibrate.runs.threads_per_run,
                     "Worker threads of each run (default: the cores shared out)")
        ->check(CLI::Range(1, 4096));
    calibrate_cmd->add_flag("--scalar", calibrate.runs.scalar, "Every run on the scalar path");
    calibrate_cmd->add_flag("--quiet,-q", calibrate.runs.quiet, "No line per iteration");
    calibrate_cmd->footer(calibrate_footer);

    KernelBenchOptions bench;
    CLI::App* bench_cmd = app.add_subcommand(
        "kernel-bench", "Time batched constitutive updates of N varied points (prints JSON)");
    bench_cmd
        ->add_option("--model", bench.model,
                     "hypoplasticity | sanisand | linear-elastic (| coulomb with --formulation "
                     "coulomb)")
        ->required();
    bench_cmd->add_option("--parameters", bench.parameters, "Built-in parameter set")
        ->capture_default_str();
    bench_cmd
        ->add_option("--formulation", bench.formulation,
                     "none (the continuum model alone) | novel | stutz | coulomb")
        ->capture_default_str();
    bench_cmd->add_option("--points", bench.points, "Number of material points")->required();
    bench_cmd->add_option("--threads", bench.threads, "Worker threads (default: all cores)")
        ->check(CLI::Range(1, 4096));
    bench_cmd->add_flag("--scalar", bench.scalar, "Use the scalar kernel path instead of SIMD");
    bench_cmd->add_option("--seconds", bench.seconds, "Time to spend in timed repetitions")
        ->capture_default_str();
    bench_cmd->add_option("--roughness", bench.roughness, "Roughness kappa in (0, 1]")
        ->capture_default_str();
    bench_cmd
        ->add_option("--increment", bench.strain_increment,
                     "Norm of every point's strain increment")
        ->capture_default_str();
    bench_cmd
        ->add_option("--scheme", bench.scheme,
                     "Substepping of the continuum models: rkf23 (Runge-Kutta-Fehlberg 2(3)) | "
                     "heun (modified Euler 1(2))")
        ->check(CLI::IsMember({"rkf23", "heun"}))
        ->capture_default_str();
    bench_cmd
        ->add_option("--tolerance", bench.tolerance,
                     "Relative local error tolerance of one substep")
        ->check(CLI::Range(1.0e-12, 0.5))
        ->capture_default_str();
    bench_cmd->add_flag("--no-split", bench.no_split,
                        "Integrate hypoplasticity's h with the stress in one scheme (the "
                        "scheme before the split; default: h on its own in each substep)");
    bench_cmd->add_flag("--implicit", bench.implicit,
                        "Sanisand only: backward-Euler steps (one per update, halved where one "
                        "does not converge) instead of explicit substeps");
    bench_cmd->add_flag("--cold", bench.cold,
                        "Every repetition starts without a carried substep size (as the first "
                        "increment of a run); default: from the size the warm-up ended with");
    bench_cmd
        ->add_option("--jacobian", bench.jacobian,
                     "Interface Jacobian: perturbation (Eq. 37, 2 ndim + 1 lanes) | "
                     "perturbation-one-side (Eq. 37 on one side, ndim + 1 lanes) | "
                     "central (those lanes as central differences) | full-perturbation "
                     "(Eqs. 39-40) | analytical (Eq. B3)")
        ->capture_default_str();
    bench_cmd
        ->add_option("--subincrement", bench.subincrement,
                     "Algorithm 1 sub-increments: fixed | adaptive")
        ->capture_default_str();
    bench_cmd
        ->add_option("--gap-increment", bench.gap_increment,
                     "Typical tangential gap increment per interface update (m)")
        ->capture_default_str();
    bench_cmd
        ->add_option("--shear-band-thickness", bench.shear_band_thickness,
                     "Interface shear band thickness d_s0 (m)")
        ->capture_default_str();
    bench_cmd->footer(bench_footer);

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int code = app.exit(e);
        return code == 0 ? exit_code::ok : exit_code::bad_input;
    }

    if (resume_cmd->parsed()) {
        resume.out = resume_dir;
        resume.scene = (std::filesystem::path(resume_dir) / "scene.toml").string();
        if (resume_progress) {
            resume.progress = ProgressMode::always;
        }
        return run_command(resume);
    }
    if (calibrate_cmd->parsed()) {
        return calibrate_command(calibrate);
    }
    if (sweep_cmd->parsed()) {
        if (sweep.out.empty() && !sweep.list) {
            fmt::print(stderr, "ifsim sweep: error: --out DIR is required (or --list)\n");
            return exit_code::bad_input;
        }
        return sweep_command(sweep);
    }
    if (run_cmd->parsed()) {
        if (progress) {
            run.progress = ProgressMode::always;
        }
        return run_command(run);
    }
    try {
        const nlohmann::ordered_json result = run_kernel_bench(bench);
        std::cout << result.dump(2) << std::endl;
        return exit_code::ok;
    } catch (const std::invalid_argument& e) {
        fmt::print(stderr, "ifsim kernel-bench: error: {}\n", e.what());
        return exit_code::bad_input;
    }
}

} // namespace ifsim::io
