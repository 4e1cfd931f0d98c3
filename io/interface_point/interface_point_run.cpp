#include "io/interface_point/interface_point_run.hpp"

#include <chrono>
#include <cmath>
#include <variant>

#include <fmt/format.h>

#include "io/output/column_units.hpp"
#include "io/output/history_writer.hpp"
#include "io/scene/interface_formulation_reader.hpp"

namespace ifsim::io {

namespace {

const std::vector<std::string> columns = {
    "step",  "t_n",    "t_t1",   "t_t2",   "s_n",    "s_p1",           "s_p2",
    "eps_n", "eps_p1", "eps_p2", "gamma1", "gamma2", "band_thickness", "e_interface"};

// A row from the point's state (model state in local axes, then the interface strains).
void write_row(HistoryWriter& h, int step, const std::array<double, 3>& traction,
               const std::vector<double>& y, std::size_t ns, const InterfaceSettings& s) {
    h.integer(step);
    for (double t : traction) {
        h.real(t);
    }
    for (std::size_t k : {0, 1, 2}) {
        h.real(y[k]);
    }
    for (int k : {contact_state::eps_n, contact_state::eps_p1, contact_state::eps_p2,
                  contact_state::gamma1, contact_state::gamma2}) {
        h.real(y[ns + static_cast<std::size_t>(k)]);
    }
    h.real(band_thickness(s, y[ns + contact_state::eps_n]));
    h.real(y[6]);
    h.end_row();
}

} // namespace

InterfacePointOutcome run_interface_point_scene(const InterfacePointScene& scene,
                                                const std::filesystem::path& dir, bool simd) {
    InterfacePointOutcome out;
    const FailedContactPoint& p = scene.point;
    const auto ns = static_cast<std::size_t>(state_size(scene.material.choice));
    HistoryWriter history(dir, columns);
    write_row(history, 0, {p.state[0], p.state[3], p.state[4]}, p.state, ns, p.options.interface);
    const auto t0 = std::chrono::steady_clock::now();
    out.call = std::visit(
        [&](const auto& params) {
            using M = typename model_of<std::decay_t<decltype(params)>>::type;
            return evaluate_contact_point<M>(params, p, simd);
        },
        scene.material.choice);
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    out.ok = out.call.report.ok();
    if (out.ok) {
        write_row(history, 1, out.call.traction, out.call.state, ns, p.options.interface);
    } else {
        out.reason = fmt::format("the interface point failed in Algorithm 1: {}",
                                 describe_interface_failure(out.call.report.first_failed_cause,
                                                            out.call.report.first_failed_residual));
    }
    history.finish();
    out.rows = history.rows();
    return out;
}

void add_interface_point_results(RunSummary& summary, const InterfacePointScene& scene,
                                 const InterfacePointOutcome& run, double parse_s) {
    const ContactReport& r = run.call.report;
    summary.ok = run.ok;
    summary.reason = run.reason;
    summary.counters = {{"lanes", r.lanes},
                        {"subincrements", r.subincrements},
                        {"newton_iterations", r.newton_iterations},
                        {"constitutive_evaluations", r.constitutive_evaluations},
                        {"model_substeps", r.model_substeps},
                        {"newton_fallbacks", r.newton_fallbacks}};
    summary.phases = {{"parse", parse_s}, {"interface", run.seconds}};
    auto& d = summary.details;
    d["columns"] = describe_columns("interface-point", columns);
    d["formulation"] = formulation_name(scene.point.options.interface.formulation);
    d["model"] = scene.material.model;
    d["parameters"] = scene.material.parameters;
    d["roughness"] = scene.material.roughness;
    d["ndim"] = scene.point.ndim;
    if (run.ok) {
        d["traction"] = {run.call.traction[0], run.call.traction[1], run.call.traction[2]};
    } else {
        d["cause"] = r.first_failed_cause;
        d["residual"] = r.first_failed_residual;
    }
    if (!scene.description.empty()) {
        d["description"] = scene.description;
    }
}

} // namespace ifsim::io
