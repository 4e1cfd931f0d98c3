#pragma once
// A scene's TOML table read for its kind: element test, interface test, boundary-value
// problem, or one interface point's Algorithm 1 call (a replay). Shared by `ifsim run` and the
// fuzzing harness of the scene reader.

#include <string>

#include <toml++/toml.h>

#include "io/boundary_value/boundary_value_scene.hpp"
#include "io/element_test/element_test_scene.hpp"
#include "io/interface_point/interface_point_scene.hpp"
#include "io/interface_test/interface_test_scene.hpp"

namespace ifsim::io {

struct Scene {
    std::string kind;
    ElementTestScene element;
    InterfaceTestScene interface;
    BoundaryValueScene boundary_value;
    InterfacePointScene interface_point;
};

// Reads `table` (the kind already in scene.kind, from scene_kind()) into the matching member.
// A boundary-value scene also reads its mesh. Throws SceneError naming `file` and the key.
void read_scene_of_kind(Scene& scene, const toml::table& table, const std::string& file);

} // namespace ifsim::io
