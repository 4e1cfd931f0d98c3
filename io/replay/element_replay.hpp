#pragma once
// The replay of an element test whose material point failed: the failed step alone, as an
// element-test scene that starts from the state the step started from ([initial] model_state),
// with the step's strain increments and stress targets and the Newton first guess the run had.

#include <filesystem>
#include <string>

#include <toml++/toml.h>

#include "io/element_test/element_test_run.hpp"
#include "io/element_test/element_test_scene.hpp"

namespace ifsim::io {

// The replay scene of a failed run (run.point_failed); `scene_table` is the run's scene with
// its overrides applied ([material] and [integration] are taken from it).
toml::table element_replay_scene(const toml::table& scene_table, const ElementTestScene& scene,
                                 const ElementRunOutcome& run);

// Writes it to DIR/replay.toml and returns the path.
std::filesystem::path write_element_replay(const std::filesystem::path& dir,
                                           const toml::table& scene_table,
                                           const ElementTestScene& scene,
                                           const ElementRunOutcome& run, bool simd);

} // namespace ifsim::io
