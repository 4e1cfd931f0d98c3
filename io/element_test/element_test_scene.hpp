#pragma once
// A scene of kind "element-test" read into what the engine's element-test driver takes:
// material, flat initial state, stages of mixed strain/stress control, and settings.

#include <string>
#include <vector>

#include <toml++/toml.h>

#include "engine/element_test_driver.hpp"
#include "io/scene/material_parameters.hpp"

namespace ifsim::io {

struct ElementTestScene {
    std::string description;
    MaterialSpec material;
    std::vector<double> initial_state;
    std::vector<ElementStage> stages;
    ElementTestSettings settings;

    long total_steps() const;
};

// Reads and checks the whole scene (every key known, every value in range). Throws SceneError.
ElementTestScene read_element_test_scene(const toml::table& scene, const std::string& file);

// Names of the six Voigt components in scene keys and CSV columns: 11 22 33 12 13 23.
inline constexpr const char* voigt_suffix[6] = {"11", "22", "33", "12", "13", "23"};

} // namespace ifsim::io
