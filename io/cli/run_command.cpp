#include "io/cli/run_command.hpp"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include <fmt/format.h>

#include "io/boundary_value/boundary_value_effects.hpp"
#include "io/boundary_value/boundary_value_run.hpp"
#include "io/boundary_value/boundary_value_scene.hpp"
#include "io/cli/exit_codes.hpp"
#include "io/cli/resumed_run.hpp"
#include "io/cli/scene_reading.hpp"
#include "io/cli/thread_limit.hpp"
#include "io/element_test/element_checkpoint.hpp"
#include "io/element_test/element_history.hpp"
#include "io/element_test/element_test_run.hpp"
#include "io/element_test/element_test_scene.hpp"
#include "io/interface_point/interface_point_run.hpp"
#include "io/interface_test/interface_checkpoint.hpp"
#include "io/interface_test/interface_test_run.hpp"
#include "io/interface_test/interface_test_scene.hpp"
#include "io/output/admissibility_warnings.hpp"
#include "io/output/atomic_file.hpp"
#include "io/output/column_units.hpp"
#include "io/output/history_results.hpp"
#include "io/output/history_writer.hpp"
#include "io/output/run_clock.hpp"
#include "io/output/run_folder.hpp"
#include "io/output/stop_signal.hpp"
#include "io/output/summary_writer.hpp"
#include "io/replay/element_replay.hpp"
#include "io/replay/interface_replay.hpp"
#include "io/scene/interface_formulation_reader.hpp"
#include "io/scene/resume_overrides.hpp"
#include "io/scene/scene_error.hpp"
#include "io/scene/scene_toml.hpp"
#include "io/scene/toml_describe.hpp"
#include "kernels/simd.hpp"

namespace ifsim::io {

namespace {

namespace fs = std::filesystem;

// DIR/scene.toml: the scene as run (overrides applied, a mesh file by its absolute path), so
// the folder says how to reproduce it.
std::string write_scene_copy(const fs::path& dir, toml::table table, const RunOptions& opt,
                             const std::string& mesh_path) {
    if (!mesh_path.empty()) {
        if (toml::table* mesh = table["mesh"].as_table()) {
            mesh->insert_or_assign("file", mesh_path);
        }
    }
    std::string header = fmt::format("# The scene as ifsim {} ({}) ran it: {}\n", build_version(),
                                     build_revision(), opt.scene);
    for (const std::string& set : opt.sets) {
        header += fmt::format("#   --set {}\n", set);
    }
    if (opt.fields) {
        header += "#   --fields\n";
    }
    if (opt.fields_every > 0) {
        header += fmt::format("#   --fields-every {}\n", opt.fields_every);
    }
    header += "# (overrides applied below; rerun: ifsim run scene.toml --out DIR)\n\n";
    std::ostringstream text;
    text << header << table << "\n";
    write_file_atomically(dir / "scene.toml", text.str());
    return text.str();
}

// DIR/scene.toml of a run resumed with changed solution controls: the old copy's header, a
// note of the changes and where they begin, then the scene with them applied. Its text is what
// the resumed run's checkpoints hold, so a later resume continues with the same settings.
std::string write_resumed_scene_copy(const fs::path& dir, const toml::table& table,
                                     const std::string& old_text,
                                     const std::vector<std::string>& sets, long increment) {
    std::string header;
    std::size_t at = 0;
    while (at < old_text.size() && old_text[at] == '#') {
        const std::size_t end = old_text.find('\n', at);
        const std::size_t stop = end == std::string::npos ? old_text.size() : end + 1;
        header.append(old_text, at, stop - at);
        at = stop;
    }
    header += fmt::format("# Resumed after increment {} by ifsim {} ({}) with\n", increment,
                          build_version(), build_revision());
    for (const std::string& set : sets) {
        header += fmt::format("#   --set {}\n", set);
    }
    header += "# (from there on not the uninterrupted run of the scene; applied below)\n\n";
    std::ostringstream text;
    text << header << table << "\n";
    write_file_atomically(dir / "scene.toml", text.str());
    return text.str();
}

// --fields and --fields-every written into the scene's [output] fields, so that the scene copy
// says what the run wrote (and `ifsim resume` writes the same).
void apply_field_switches(toml::table& table, const RunOptions& opt) {
    if (!opt.fields && opt.fields_every <= 0) {
        return;
    }
    if (table.contains("output") && !table["output"].is_table()) {
        return; // the scene reader names the mistake
    }
    toml::table* output = table["output"].as_table();
    if (output == nullptr) {
        table.insert_or_assign("output", toml::table{});
        output = table["output"].as_table();
    }
    toml::table fields;
    bool stages = false;
    if (const toml::node* f = output->get("fields")) {
        if (const auto b = f->value<bool>()) {
            stages = *b;
        } else if (const toml::table* t = f->as_table()) {
            fields = *t;
            const toml::node* st = t->get("stages");
            if (st != nullptr && !st->is_boolean()) {
                return; // the scene reader names the mistake
            }
            stages = (*t)["stages"].value_or(true);
        } else {
            return; // neither true/false nor a table: the scene reader names the mistake
        }
    }
    fields.insert_or_assign("stages", stages || opt.fields);
    if (opt.fields_every > 0) {
        fields.insert_or_assign("every", static_cast<std::int64_t>(opt.fields_every));
    }
    output->insert_or_assign("fields", std::move(fields));
}

std::string read_text_file(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

// The --set assignment an error key comes from, if any (the key itself or a key below it).
std::optional<std::string> override_behind(const std::string& key,
                                           const std::vector<std::string>& sets) {
    for (auto it = sets.rbegin(); it != sets.rend(); ++it) {
        const std::string k = override_key(*it);
        if (!k.empty() && (key == k || key.starts_with(k + ".") || k.starts_with(key + "."))) {
            return *it;
        }
    }
    return std::nullopt;
}

nlohmann::ordered_json element_counters(const ElementTestCounters& c) {
    return {{"increments", c.increments},
            {"newton_iterations", c.newton_iterations},
            {"subincrements", static_cast<long long>(std::llround(c.substeps))},
            {"constitutive_evaluations", c.constitutive_evaluations},
            {"rejected_substeps", static_cast<long long>(std::llround(c.rejected_substeps))},
            {"rate_evaluations", static_cast<long long>(std::llround(c.rate_evaluations))},
            {"unreliable_updates", c.unreliable_updates},
            {"frozen_substep_retries", c.frozen_substep_retries}};
}

// What an element-test run adds to its summary: status, counters, phases and the material.
void add_element_test_results(RunSummary& summary, const ElementTestScene& scene,
                              const ElementRunOutcome& run, double parse_s) {
    const ElementTestResult& r = run.result;
    summary.ok = r.ok;
    summary.reason = r.reason;
    summary.counters = element_counters(r.counters);
    if (r.counters.unreliable_updates > 0) {
        summary.warnings.push_back(
            {"unreliable_updates", static_cast<double>(r.counters.unreliable_updates),
             fmt::format("{} material update(s) ended on a safeguard (tension cut-off or the "
                         "substep floor): the stress path there is not the model's own",
                         r.counters.unreliable_updates)});
    }
    add_admissibility(summary, run.admissibility, "material", scene.material.model);
    summary.details["model"] = scene.material.model;
    summary.details["parameters"] = scene.material.parameters;
    summary.details["roughness"] = scene.material.roughness;
    summary.details["stages"] = scene.stages.size();
    summary.details["steps"] = scene.total_steps();
    summary.details["rows"] = run.rows;
    summary.details["outputs"] = {HistoryWriter::file_name};
    summary.details["columns"] =
        describe_columns("element-test", element_history_columns(scene.material.choice));
    if (!scene.description.empty()) {
        summary.details["description"] = scene.description;
    }
    // Rows are written from the driver's callback: their time is output, not driver time.
    summary.phases = {{"parse", parse_s},
                      {"constitutive", r.constitutive_seconds},
                      {"driver", std::max(0.0, r.driver_seconds - run.row_seconds)},
                      {"output", run.row_seconds + run.finish_seconds}};
}

int write_summary_or_report(const fs::path& dir, const RunSummary& summary, int code) {
    try {
        write_summary(dir, summary);
    } catch (const std::exception& e) {
        fmt::print(stderr, "ifsim: error: {}\n", e.what());
        return exit_code::io_error;
    }
    return code;
}

// Checkpoints written by a run, for summary.json.
struct CheckpointCount {
    long written = 0;
    double seconds = 0.0;
};

// Writes the replay of a failed point (io/replay/) and names it in the summary and its reason;
// a replay that cannot be written is a note, not a second failure.
template <class Write>
void note_replay(RunSummary& summary, Write write) {
    try {
        const fs::path path = write();
        summary.details["replay"] = path.string();
        summary.reason += fmt::format(" (replay: ifsim run {})", path.string());
    } catch (const std::exception& e) {
        summary.warnings.push_back({"replay_not_written", 1.0, e.what()});
    }
}

// Runs the scene's kind and fills the summary with its results. Throws std::runtime_error when
// history.csv cannot be written at all.
void run_kind(Scene& scene, const toml::table& table, const RunOptions& opt, const fs::path& dir,
              double parse_s, const CheckpointRequest& checkpoints, const ResumedRun* resumed,
              RunSummary& summary, CheckpointCount& written, std::string& label, long& steps) {
    const ProgressMode progress = opt.quiet ? ProgressMode::never : opt.progress;
    const bool simd = resumed ? resumed->run().simd : !opt.scalar;
    if (scene.kind == "boundary-value") {
        BoundaryValueScene& s = scene.boundary_value;
        if (!opt.quiet) {
            fmt::print(stderr, "ifsim: {}: {}\n", opt.scene,
                       describe_effects(boundary_value_effects(s)));
        }
        BoundaryValueCheckpointing bv;
        static_cast<CheckpointRequest&>(bv) = checkpoints;
        bv.resume = resumed ? &resumed->boundary_value : nullptr;
        const BoundaryValueRunOutcome run =
            run_boundary_value_scene(s, dir, progress, simd, bv, opt.iteration_log);
        add_boundary_value_results(summary, s, run, parse_s);
        if (run.costliest_call && run.costliest_call_error.empty()) {
            const FailedContactPoint& c = *run.costliest_call;
            summary.details["costliest_call"] = {
                {"replay", (dir / costliest_call_file_name).string()},
                {"where", c.where},
                {"model_substeps", c.model_substeps},
                {"failure", c.cause == 0.0 ? std::string("none")
                                           : std::string(interface_failure::describe(c.cause))}};
        } else if (run.costliest_call) {
            summary.warnings.push_back(
                {"costliest_call_not_written", 1.0, run.costliest_call_error});
        }
        if (run.failed_point) {
            note_replay(summary, [&] {
                return write_interface_replay(dir, *run.failed_point,
                                              s.contacts[run.failed_pair].formulation.material,
                                              summary.reason, simd);
            });
        }
        written = {run.checkpoints, run.checkpoint_seconds};
        label = fmt::format("{}D FE", s.mesh_spec.dimension);
        if (s.contacts.size() == 1) {
            label += ", " + s.contacts.front().formulation.name();
        } else if (!s.contacts.empty()) {
            label += fmt::format(", {} contact pairs", s.contacts.size());
        }
        steps = s.total_steps();
        return;
    }
    if (scene.kind == "interface-point") {
        const InterfacePointScene& s = scene.interface_point;
        const InterfacePointOutcome run = run_interface_point_scene(s, dir, simd);
        add_interface_point_results(summary, s, run, parse_s);
        label =
            fmt::format("one interface point, {} {}",
                        formulation_name(s.point.options.interface.formulation), s.material.model);
        steps = 1;
        return;
    }
    if (scene.kind == "interface-test") {
        InterfaceTestScene& s = scene.interface;
        s.spec.contact.simd = simd;
        s.spec.sample_update.simd = simd;
        const InterfaceRunOutcome run = run_interface_test_scene(
            s, dir, progress, checkpoints, resumed ? &resumed->interface : nullptr);
        add_interface_test_results(summary, s, run, parse_s);
        if (run.result.failed_point) {
            note_replay(summary, [&] {
                return write_interface_replay(dir, *run.result.failed_point, s.interface_material,
                                              summary.reason, simd);
            });
        }
        written = {run.checkpoints, run.checkpoint_seconds};
        const std::string_view f = formulation_name(s.spec.contact.interface.formulation);
        label = s.coulomb() ? std::string(f) : fmt::format("{} {}", f, s.interface_material.model);
        steps = s.total_steps();
        return;
    }
    ElementTestScene& s = scene.element;
    s.settings.update.simd = simd;
    const ElementRunOutcome run = run_element_test_scene(s, dir, progress, checkpoints,
                                                         resumed ? &resumed->element : nullptr);
    add_element_test_results(summary, s, run, parse_s);
    if (run.point_failed) {
        note_replay(summary, [&] { return write_element_replay(dir, table, s, run, simd); });
    }
    written = {run.checkpoints, run.checkpoint_seconds};
    label = s.material.model;
    steps = s.total_steps();
}

} // namespace

int run_command(const RunOptions& opt) {
    const auto t_start = Clock::now();
    const ThreadLimit threads(opt.threads);
    const fs::path dir(opt.out);
    RunSummary summary;
    summary.scene = opt.scene;
    summary.threads = threads.threads();
    summary.details["overrides"] = opt.sets;

    // Resume: the checkpoint and the scene copy of DIR, checked against each other before
    // anything in DIR changes.
    std::optional<ResumedRun> checkpoint;
    std::string scene_text;
    const auto kernel_path = [&](bool scalar) {
        summary.details["path"] = scalar ? "scalar" : "simd";
        summary.details["lanes"] = scalar ? std::size_t{1} : simd::lanes;
    };
    kernel_path(opt.scalar);
    if (opt.resume) {
        try {
            checkpoint.emplace(dir);
        } catch (const std::exception& e) {
            fmt::print(stderr, "ifsim: error: cannot resume: {}\n", e.what());
            return exit_code::bad_input;
        }
        kernel_path(!checkpoint->run().simd); // a resumed run keeps the path it started with
        scene_text = read_text_file(dir / "scene.toml");
        if (scene_text != checkpoint->run().scene_text) {
            fmt::print(stderr,
                       "ifsim: error: cannot resume: {} is not the scene the checkpoint was "
                       "written for (changed since the run started)\n",
                       (dir / "scene.toml").string());
            return exit_code::bad_input;
        }
        // Changed solution controls from here on: refused before anything in DIR changes.
        for (const std::string& set : opt.sets) {
            std::string why = checkpoint->kind != "boundary-value"
                                  ? fmt::format("--set {}: only a boundary-value run can be "
                                                "resumed with changed settings",
                                                set)
                                  : resume_override_refusal(set);
            if (!why.empty()) {
                fmt::print(stderr, "ifsim: error: cannot resume {}: {}\n", dir.string(), why);
                return exit_code::bad_input;
            }
        }
    }

    // Parse: the scene, the overrides, the kind's schema.
    Scene scene;
    toml::table table;
    std::string mesh_path; // a boundary-value scene's mesh file, resolved
    std::string scene_error;
    try {
        table = load_scene_table(opt.scene);
        for (const auto& set : opt.sets) {
            apply_override(table, set, opt.scene);
        }
        scene.kind = scene_kind(table, opt.scene);
        summary.kind = scene.kind;
        if (scene.kind == "boundary-value") {
            apply_field_switches(table, opt);
        }
        read_scene_of_kind(scene, table, opt.scene);
        if (scene.kind == "boundary-value" && !scene.boundary_value.mesh_spec.file.empty()) {
            mesh_path = fs::absolute(scene.boundary_value.mesh_spec.path).string();
        }
    } catch (const SceneError& e) {
        scene_error = e.what();
        if (const auto set = override_behind(e.key(), opt.sets)) {
            scene_error += fmt::format(" (from --set {})", *set);
        }
    }
    // The folder is prepared once the scene is read: the files being run (a scene copy run
    // in place, its mesh) stay, and a scene error never removes an earlier run (--replace
    // applies to runs that start).
    FolderPreparation earlier;
    try {
        // Resuming: DIR is the run being continued, nothing moves.
        std::vector<fs::path> keep = {opt.scene};
        if (!mesh_path.empty()) {
            keep.emplace_back(mesh_path);
        }
        if (!opt.resume) {
            earlier = prepare_run_folder(dir, opt.replace && scene_error.empty(), keep);
        }
    } catch (const std::exception& e) {
        fmt::print(stderr, "ifsim: error: {}\n", e.what());
        return exit_code::io_error;
    }
    if (!earlier.moved.empty() && !opt.quiet) {
        fmt::print(stderr, "ifsim: {}\n", earlier.message(dir));
    }
    if (!earlier.moved.empty()) {
        summary.details["earlier_run"] = {
            {"files", earlier.moved},
            {"moved_to", earlier.removed ? nlohmann::ordered_json(nullptr)
                                         : nlohmann::ordered_json(earlier.moved_to.string())}};
    }
    if (!scene_error.empty()) {
        fmt::print(stderr, "ifsim: error: {}\n", scene_error);
        summary.ok = false;
        summary.reason = "scene error: " + scene_error;
        summary.wall_s = since(t_start);
        summary.phases = {{"parse", summary.wall_s}};
        return write_summary_or_report(dir, summary, exit_code::bad_input);
    }
    const double parse_s = since(t_start);
    if (!opt.resume) {
        try {
            scene_text = write_scene_copy(dir, table, opt, mesh_path);
        } catch (const std::exception& e) {
            fmt::print(stderr, "ifsim: error: {}\n", e.what());
            return exit_code::io_error;
        }
    }
    summary.details["scene_copy"] = "scene.toml";
    // A resumed run: the checkpoint must fit the scene before history.csv is cut back.
    if (checkpoint) {
        const std::string why = scene.kind == "element-test" ? checkpoint->mismatch(scene.element)
                                : scene.kind == "interface-test"
                                    ? checkpoint->mismatch(scene.interface)
                                    : checkpoint->mismatch(scene.boundary_value);
        if (!why.empty() || checkpoint->kind != scene.kind) {
            fmt::print(stderr, "ifsim: error: cannot resume: {} does not fit {}: {}\n",
                       (dir / checkpoint_file_name).string(), (dir / "scene.toml").string(),
                       why.empty() ? "it is of another scene kind" : why);
            return exit_code::bad_input;
        }
        if (!opt.sets.empty()) {
            try {
                scene_text = write_resumed_scene_copy(dir, table, scene_text, opt.sets,
                                                      checkpoint->run().increment);
            } catch (const std::exception& e) {
                fmt::print(stderr, "ifsim: error: {}\n", e.what());
                return exit_code::io_error;
            }
            summary.details["resumed_with"] = {{"after_increment", checkpoint->run().increment},
                                               {"overrides", opt.sets}};
        }
        // The stopped run's summary.json ("failed", interrupted) no longer describes the
        // folder; the resumed run writes its own at its end.
        std::error_code ignored;
        fs::remove(dir / summary_file_name, ignored);
    }
    // Options of boundary-value runs given for another kind: a bad command line.
    const bool fields = opt.fields || opt.fields_every > 0;
    if ((fields || opt.iteration_log) && scene.kind != "boundary-value") {
        const std::string message = fmt::format(
            "{} appl{} to boundary-value scenes (the others have no {}); {} is a scene of kind "
            "\"{}\"",
            fields ? "--fields and --fields-every" : "--iteration-log", fields ? "y" : "ies",
            fields ? "field" : "Newton iteration", opt.scene, scene.kind);
        fmt::print(stderr, "ifsim: error: {}\n", message);
        summary.ok = false;
        summary.reason = message;
        summary.wall_s = since(t_start);
        return write_summary_or_report(dir, summary, exit_code::bad_input);
    }
    CheckpointRequest checkpoints;
    checkpoints.every = opt.checkpoint_every;
    checkpoints.minutes = opt.checkpoint_minutes;
    checkpoints.scene_text = scene_text;
    if (checkpoint && !checkpoints.enabled()) { // a resumed run keeps its interval
        checkpoints.every = checkpoint->run().every;
        checkpoints.minutes = checkpoint->run().minutes;
    }
    std::string label;
    long steps = 0;
    CheckpointCount written;
    // Stop signals end the run at the next step; a step that does not end within the grace
    // still leaves a summary (the watchdog's, written from what was known before the run).
    const StopSignals stop_signals;
    const RunSummary before = summary;
    StopWatchdog watchdog(stop_grace, [&before, &dir, t_start](int sig) {
        RunSummary last = before;
        last.ok = false;
        last.reason = fmt::format("interrupted by {}: the step under way did not end within {} s "
                                  "of the signal; history.csv holds the steps before it",
                                  signal_name(sig), stop_grace.count() / 1000.0);
        last.details["interrupted"] = signal_name(sig);
        last.wall_s = since(t_start);
        std::error_code ec;
        fs::rename(dir / HistoryWriter::partial_name, dir / HistoryWriter::file_name, ec);
        try {
            write_summary(dir, last);
            fmt::print(stderr, "\nifsim: run failed: {}\n", last.reason);
        } catch (const std::exception&) {
        }
    });
    try {
        run_kind(scene, table, opt, dir, parse_s, checkpoints, checkpoint ? &*checkpoint : nullptr,
                 summary, written, label, steps);
        if (auto results = history_results(dir / HistoryWriter::file_name); !results.empty()) {
            summary.details["results"] = std::move(results);
        }
        if (summary.details.contains("effects")) {
            summary.details["effects"]["checkpoints"] = checkpoints.enabled();
        }
        if (checkpoints.enabled()) {
            summary.details["checkpoints"] = {{"every", checkpoints.every},
                                              {"minutes", checkpoints.minutes},
                                              {"written", written.written},
                                              {"seconds", written.seconds}};
        }
        if (checkpoint) {
            summary.details["resumed"] = {{"from_increment", checkpoint->run().increment},
                                          {"times", checkpoint->run().resumes + 1}};
        }
    } catch (const std::exception& e) {
        if (!watchdog.disarm()) {
            return exit_code::io_error; // not reached: the watchdog ends the process
        }
        fmt::print(stderr, "ifsim: error: {}\n", e.what());
        summary.ok = false;
        summary.reason = e.what();
        summary.wall_s = since(t_start);
        write_summary_or_report(dir, summary, exit_code::io_error);
        return exit_code::io_error;
    }
    if (!watchdog.disarm()) {
        return exit_code::io_error; // not reached: the watchdog ends the process
    }
    summary.wall_s = since(t_start);
    if (const int sig = stop_signal(); sig != 0 && !summary.ok) {
        summary.details["interrupted"] = signal_name(sig);
        fmt::print(stderr, "ifsim: run failed: {}\n", summary.reason);
        return write_summary_or_report(dir, summary, interrupted_exit_code(sig));
    }

    // A degraded result is printed even with --quiet: a reader must not miss it.
    for (const RunWarning& w : summary.warnings) {
        fmt::print(stderr, "ifsim: WARNING: degraded result: {}\n", w.message);
    }
    if (!summary.ok) {
        fmt::print(stderr, "ifsim: run failed: {}\n", summary.reason);
        return write_summary_or_report(dir, summary, exit_code::run_failed);
    }
    const int code = write_summary_or_report(dir, summary, exit_code::ok);
    if (code == exit_code::ok && !opt.quiet) {
        fmt::print("ifsim: {} ({}) ok{}: {} steps in {:.3f} s, results in {}\n", opt.scene, label,
                   summary.warnings.empty() ? "" : ", DEGRADED (warnings above, summary.json)",
                   steps, summary.wall_s, opt.out);
    }
    return code;
}

} // namespace ifsim::io
