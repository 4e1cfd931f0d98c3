#pragma once
// What a boundary-value run builds (summary.json "effects": "only what the scene asks for"
// made visible), and the same as one line for the console.

#include <string>

#include <nlohmann/json.hpp>

#include "io/boundary_value/boundary_value_scene.hpp"

namespace ifsim::io {

nlohmann::ordered_json boundary_value_effects(const BoundaryValueScene& scene);
std::string describe_effects(const nlohmann::ordered_json& effects);

} // namespace ifsim::io
