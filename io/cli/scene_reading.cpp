#include "io/cli/scene_reading.hpp"

#include <fmt/format.h>

#include "io/scene/scene_error.hpp"
#include "io/scene/toml_describe.hpp"

namespace ifsim::io {

void read_scene_of_kind(Scene& scene, const toml::table& table, const std::string& file) {
    if (scene.kind == "element-test") {
        scene.element = read_element_test_scene(table, file);
    } else if (scene.kind == "interface-test") {
        scene.interface = read_interface_test_scene(table, file);
    } else if (scene.kind == "boundary-value") {
        scene.boundary_value = read_boundary_value_scene(table, file);
    } else if (scene.kind == "interface-point") {
        scene.interface_point = read_interface_point_scene(table, file);
    } else {
        throw SceneError(file, "kind",
                         fmt::format("kind \"{}\" is not supported by this build; expected "
                                     "\"element-test\", \"interface-test\", "
                                     "\"boundary-value\" or \"interface-point\"",
                                     scene.kind),
                         line_in_file(*table.get("kind")));
    }
}

} // namespace ifsim::io
