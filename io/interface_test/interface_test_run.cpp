#include "io/interface_test/interface_test_run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>

#include <fmt/format.h>

#include "io/interface_test/interface_history.hpp"
#include "io/output/admissibility_warnings.hpp"
#include "io/output/column_units.hpp"
#include "io/output/history_writer.hpp"
#include "io/output/run_clock.hpp"
#include "io/output/step_checkpoints.hpp"
#include "io/output/stop_signal.hpp"
#include "io/scene/interface_formulation_reader.hpp"

namespace ifsim::io {

namespace {

// The sample's and the band's states of a row, checked against their models' sand region
// (engine/state_admissibility.hpp). The band carries the plate's shear traction (in series).
void check_row(const InterfaceTestScene& scene, const InterfaceRow& r, InterfaceRunOutcome& out) {
    const double sample[7] = {r.sample_s11, r.sample_s22, r.sample_s33, r.sample_s12,
                              r.sample_s13, 0.0,          r.e_sample};
    check_state(scene.sample_material.choice, sample, r.step, out.sample_admissibility);
    if (!scene.coulomb()) {
        const double band[7] = {r.s_n, r.s_p1, r.s_p2, r.t_t1, r.t_t2, 0.0, r.e_interface};
        check_state(scene.interface_material.choice, band, r.step, out.admissibility);
    }
}

} // namespace

InterfaceRunOutcome run_interface_test_scene(const InterfaceTestScene& scene,
                                             const std::filesystem::path& dir,
                                             ProgressMode progress,
                                             const CheckpointRequest& checkpoints,
                                             const InterfaceTestCheckpoint* resume) {
    InterfaceRunOutcome out;
    HistoryWriter history =
        open_history(dir, interface_history_columns(), resume ? &resume->run : nullptr);
    ProgressLine line(progress, scene.total_steps(), static_cast<int>(scene.spec.stages.size()));
    const double t_N0 = scene.initial_normal_stress();
    const double K =
        scene.spec.control == NormalControl::constant_stiffness ? scene.spec.normal_stiffness : 0.0;
    const auto on_row = [&](const InterfaceRow& row) {
        const auto t0 = Clock::now();
        write_interface_row(history, row, contact_normal_stress(t_N0, K, row));
        check_row(scene, row, out);
        line.update(row.step, row.stage);
        out.row_seconds += since(t0);
        if (!checkpoints.enabled()) { // else StepCheckpoints writes one first
            throw_if_stopped(fmt::format("step {} of {}", row.step, scene.total_steps()), false);
        }
    };
    StepCheckpoints<InterfaceTestCheckpoint, InterfaceTestPosition> saved(
        checkpoints, "interface-test", scene.spec.contact.simd, resume, history, dir,
        &write_interface_test_checkpoint, scene.total_steps());
    try {
        out.result = run_interface_test(scene.spec, on_row, resume ? &resume->position : nullptr,
                                        saved.callback());
    } catch (const RunInterrupted& e) {
        out.result.ok = false;
        out.result.reason = e.what();
    } catch (const std::exception& e) {
        // A writer or engine error in the middle of the run: keep the rows so far.
        out.result.ok = false;
        out.result.reason = fmt::format("run aborted: {}", e.what());
    }
    line.finish();
    out.checkpoints = saved.written();
    out.checkpoint_seconds = saved.seconds();
    if (out.result.ok) {
        remove_checkpoint(dir);
    }
    const auto t1 = Clock::now();
    history.finish();
    out.finish_seconds = since(t1);
    out.rows = history.rows();
    return out;
}

void add_interface_test_results(RunSummary& summary, const InterfaceTestScene& scene,
                                const InterfaceRunOutcome& run, double parse_s) {
    const InterfaceTestResult& r = run.result;
    const InterfaceTestCounters& c = r.counters;
    summary.ok = r.ok;
    summary.reason = r.reason;
    summary.counters = {{"increments", c.increments},
                        {"newton_iterations", c.newton_iterations},
                        {"step_cuts", c.step_cuts},
                        {"band_clamped_steps", c.band_clamped_steps},
                        {"frozen_retries", c.frozen_retries},
                        {"stagnation_accepts", c.stagnation_accepts},
                        {"subincrements", rounded(c.subincrements)},
                        {"constitutive_evaluations", rounded(c.constitutive_evaluations)},
                        {"interface_newton_iterations", rounded(c.interface_newton_iterations)},
                        {"interface_evaluations", rounded(c.interface_evaluations)},
                        {"interface_newton_fallbacks", rounded(c.interface_newton_fallbacks)},
                        {"sample_evaluations", rounded(c.sample_evaluations)},
                        {"model_substeps", rounded(c.model_substeps)}};
    if (c.band_clamped_steps > 0) {
        summary.warnings.push_back(
            {"band_clamped", static_cast<double>(c.band_clamped_steps),
             fmt::format("{} of {} steps ran on a clamped shear band (d_s held at "
                         "min_band_fraction x d_s0 = {:.3g} m): those rows rest on an assumed "
                         "band thickness, not Eq. 26",
                         c.band_clamped_steps, run.rows > 0 ? run.rows - 1 : 0,
                         scene.spec.contact.interface.min_band_fraction *
                             scene.spec.contact.interface.shear_band_thickness)});
    }
    add_admissibility(summary, run.sample_admissibility, "sample", scene.sample_material.model);
    if (!scene.coulomb()) {
        add_admissibility(summary, run.admissibility, "interface", scene.interface_material.model);
    }
    auto& d = summary.details;
    d["columns"] = describe_columns("interface-test", interface_history_columns());
    const InterfaceTestSpec& spec = scene.spec;
    d["formulation"] = formulation_name(spec.contact.interface.formulation);
    if (scene.coulomb()) {
        d["friction_coefficient"] = spec.coulomb.friction_coefficient;
        d["tangential_stiffness"] = spec.coulomb.tangential_stiffness;
    } else {
        const InterfaceSettings& s = spec.contact.interface;
        d["model"] = scene.interface_material.model;
        d["parameters"] = scene.interface_material.parameters;
        d["roughness"] = scene.interface_material.roughness;
        d["shear_band_thickness"] = s.shear_band_thickness;
        d["band_collapse"] = s.clamp_band ? "clamp" : "fail";
        d["min_band_fraction"] = s.min_band_fraction;
        if (spec.contact.interface.formulation == InterfaceFormulation::stutz) {
            d["stutz_initial_stress"] = scene.stutz_initial_stress;
        }
        d["subincrement"] = scene.subincrement;
        d["max_subincrement"] = s.max_subincrement;
        d["tolerance"] = s.tolerance;
        d["jacobian"] = scene.jacobian;
        d["perturbation"] = spec.contact.perturbation;
    }
    d["sample_model"] = scene.sample_material.model;
    d["sample_parameters"] = scene.sample_material.parameters;
    d["height"] = spec.height;
    d["normal_control"] = scene.normal_control;
    d["initial_normal_stress"] = scene.initial_normal_stress();
    if (spec.control == NormalControl::constant_stiffness) {
        d["normal_stiffness"] = spec.normal_stiffness; // kPa/m
    }
    d["stages"] = spec.stages.size();
    d["steps"] = scene.total_steps();
    d["rows"] = run.rows;
    d["outputs"] = {HistoryWriter::file_name};
    if (!scene.description.empty()) {
        d["description"] = scene.description;
    }
    // Rows are written from the driver's callback: their time is output, not driver time.
    summary.phases = {{"parse", parse_s},
                      {"interface", r.interface_seconds},
                      {"sample", r.sample_seconds},
                      {"driver", std::max(0.0, r.driver_seconds - run.row_seconds)},
                      {"output", run.row_seconds + run.finish_seconds}};
}

} // namespace ifsim::io
