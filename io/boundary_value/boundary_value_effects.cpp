#include "io/boundary_value/boundary_value_effects.hpp"

#include <algorithm>
#include <variant>
#include <vector>

#include <fmt/format.h>

namespace ifsim::io {

nlohmann::ordered_json boundary_value_effects(const BoundaryValueScene& scene) {
    nlohmann::ordered_json materials = nlohmann::ordered_json::array();
    std::vector<std::string> seen;
    for (const BodySpec& b : scene.bodies) {
        if (std::find(seen.begin(), seen.end(), b.material) != seen.end()) {
            continue;
        }
        seen.push_back(b.material);
        const BodyMaterial& m = scene.materials.at(b.name);
        nlohmann::ordered_json j = {{"name", b.material}, {"model", m.spec.model}};
        if (const auto* h = std::get_if<HypoplasticityParams>(&m.set.material)) {
            j["intergranular_strain"] = h->intergranular_strain;
        }
        j["k0"] = m.geostatic;
        materials.push_back(j);
    }
    nlohmann::ordered_json contacts = nlohmann::ordered_json::array();
    for (const BoundaryValueInterface& c : scene.contacts) {
        nlohmann::ordered_json j = {{"name", c.pair.name}, {"formulation", c.formulation.name()}};
        if (!c.formulation.is_coulomb()) {
            j["model"] = c.formulation.material.model;
        }
        contacts.push_back(j);
    }
    bool gravity = false, springs = false, pressures = false;
    for (const fem::Stage& st : scene.stages) {
        gravity = gravity || st.gravity.has_value();
        springs = springs || !st.springs.empty();
        pressures = pressures || !st.pressures.empty();
    }
    const FieldSchedule& f = scene.output.fields;
    return {{"kinematics", scene.mesh_spec.kinematics},
            {"dimension", scene.mesh_spec.dimension},
            {"materials", materials},
            {"contact_pairs", contacts},
            {"gravity", gravity},
            {"pressures", pressures},
            {"springs", springs},
            {"fields", f.enabled()},
            {"checkpoints", false}}; // set by the run (a command-line option)
}

std::string describe_effects(const nlohmann::ordered_json& e) {
    std::string materials;
    for (const auto& m : e["materials"]) {
        materials +=
            fmt::format("{}{} ({}{}{})", materials.empty() ? "" : ", ",
                        m["name"].get<std::string>(), m["model"].get<std::string>(),
                        m.contains("intergranular_strain")
                            ? (m["intergranular_strain"].get<bool>() ? ", IGS" : ", no IGS")
                            : "",
                        m["k0"].get<bool>() ? ", K0" : "");
    }
    std::string contacts;
    for (const auto& c : e["contact_pairs"]) {
        const std::string model = c.value("model", std::string());
        contacts +=
            fmt::format("{}{} ({}{}{})", contacts.empty() ? "" : ", ", c["name"].get<std::string>(),
                        c["formulation"].get<std::string>(), model.empty() ? "" : " ", model);
    }
    const auto on = [&](const char* k) { return e[k].get<bool>() ? "yes" : "no"; };
    return fmt::format("{}D, {}; materials: {}; contact: {}; gravity: {}; fields: {}",
                       e["dimension"].get<int>(), e["kinematics"].get<std::string>(), materials,
                       contacts.empty() ? "none" : contacts, on("gravity"), on("fields"));
}

} // namespace ifsim::io
