#include "io/replay/interface_replay.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "io/interface_point/algorithm1_options.hpp"
#include "io/interface_point/interface_point_scene.hpp"
#include "io/replay/replay_file.hpp"
#include "io/scene/interface_formulation_reader.hpp"

namespace ifsim::io {

toml::table interface_replay_scene(const FailedContactPoint& point, const MaterialSpec& material,
                                   const std::string& description) {
    toml::table iface;
    iface.insert("formulation", std::string(formulation_name(point.options.interface.formulation)));
    iface.insert("model", material.model);
    if (material.parameters == "inline") {
        iface.insert("parameters", material.inline_parameters);
    } else {
        iface.insert("parameters", material.parameters);
    }
    iface.insert("roughness", material.roughness);

    toml::table out;
    out.insert("kind", "interface-point");
    out.insert("description", description);
    out.insert("interface", std::move(iface));
    out.insert("algorithm1", algorithm1_table(point.options));
    out.insert("point", point_table(point, state_size(material.choice)));
    out.insert("increment", increment_table(point));
    return out;
}

std::filesystem::path write_interface_replay(const std::filesystem::path& dir,
                                             const FailedContactPoint& point,
                                             const MaterialSpec& material,
                                             const std::string& run_reason, bool simd) {
    const auto finite = [](const auto& values) {
        return std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); });
    };
    if (!finite(point.state) || !finite(point.inputs)) {
        throw std::runtime_error(fmt::format("the failed call of {} has non-finite inputs or "
                                             "state; nothing a scene can replay",
                                             point.where));
    }
    const std::string description =
        fmt::format("replay of the Algorithm 1 call of {} that failed: {}", point.where,
                    describe_interface_failure(point.cause, point.residual));
    return write_replay(
        dir, interface_replay_scene(point, material, description),
        fmt::format("{} failed in Algorithm 1; the run: {}", point.where, run_reason), simd);
}

std::filesystem::path write_costliest_call_replay(const std::filesystem::path& dir,
                                                  const FailedContactPoint& point,
                                                  const MaterialSpec& material, bool simd) {
    const std::string cost =
        fmt::format("the costliest Algorithm 1 call of the run, {} at {:.4g} interface-model "
                    "substeps ({})",
                    point.where, point.model_substeps,
                    point.cause == 0.0 ? std::string("it succeeded")
                                       : describe_interface_failure(point.cause, point.residual));
    return write_replay(dir, interface_replay_scene(point, material, "replay of " + cost), cost,
                        simd, costliest_call_file_name,
                        "costs the same (summary.json: counters.model_substeps)");
}

} // namespace ifsim::io
