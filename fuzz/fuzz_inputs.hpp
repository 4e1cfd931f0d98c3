#pragma once
// What the fuzzing harnesses do with one input, shared with the regression test that replays
// every input the fuzzers once crashed on (fuzz/regressions/,
// tests/io/scene/test_fuzz_regressions.cpp). The defined answer to a bad input is SceneError or
// MeshFileError, caught here; any other exception, a sanitizer report or a hang is a bug.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "io/cli/scene_reading.hpp"
#include "io/mesh/gmsh_error.hpp"
#include "io/mesh/gmsh_parse.hpp"
#include "io/mesh/gmsh_reader.hpp"
#include "io/scene/scene_error.hpp"
#include "io/scene/scene_toml.hpp"

namespace ifsim::fuzz {

// Any bytes given to the Gmsh reader as a mesh file (ASCII or binary).
inline void read_gmsh_input(std::string_view input) {
    try {
        const io::GmshMesh mesh =
            io::build_gmsh_mesh(io::parse_gmsh_bytes(std::string(input), "fuzz.msh"));
        (void)mesh;
    } catch (const io::MeshFileError&) {
    }
}

// True when some body asks for more than 100 000 generated elements: the reader accepts up
// to 10 million per body, and memory use is not what the fuzzer tests.
inline bool large_generated_mesh(const toml::node& node) {
    if (const toml::table* t = node.as_table()) {
        for (const auto& [key, value] : *t) {
            if (key.str() == "elements" && value.is_array()) {
                double product = 1.0;
                for (const toml::node& n : *value.as_array()) {
                    product *= static_cast<double>(n.value_or<std::int64_t>(1));
                }
                if (product > 1e5) {
                    return true;
                }
            }
            if (large_generated_mesh(value)) {
                return true;
            }
        }
    } else if (const toml::array* a = node.as_array()) {
        for (const toml::node& n : *a) {
            if (large_generated_mesh(n)) {
                return true;
            }
        }
    }
    return false;
}

// A scene's TOML text, then optionally a line "%%" and one --set KEY=VALUE per line, read as
// `scene_file` (mesh files named in it are found relative to that path).
inline void read_scene_input(std::string_view input, const std::string& scene_file) {
    const std::size_t separator = input.find("\n%%\n");
    const std::string_view text = input.substr(0, separator);
    std::vector<std::string_view> overrides;
    if (separator != std::string_view::npos) {
        std::string_view rest = input.substr(separator + 4);
        while (!rest.empty()) {
            const std::size_t end = rest.find('\n');
            overrides.push_back(rest.substr(0, end));
            rest = end == std::string_view::npos ? std::string_view() : rest.substr(end + 1);
        }
    }
    try {
        toml::table table = io::parse_scene_text(text, scene_file);
        for (const std::string_view set : overrides) {
            io::apply_override(table, set, scene_file);
        }
        if (large_generated_mesh(table)) {
            return;
        }
        io::Scene scene;
        scene.kind = io::scene_kind(table, scene_file);
        io::read_scene_of_kind(scene, table, scene_file);
    } catch (const io::SceneError&) {
    }
}

} // namespace ifsim::fuzz
