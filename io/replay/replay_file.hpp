#pragma once
// Writing a replay scene: a small scene that reproduces a failed material or contact point
// with `ifsim run`, written as DIR/replay.toml next to the failed run's results. The TOML is
// printed by toml++ with 17 significant digits, so every number reads back bit for bit.

#include <filesystem>
#include <span>
#include <string>

#include <toml++/toml.h>

namespace ifsim::io {

inline constexpr const char* replay_file_name = "replay.toml";

// A TOML array of the numbers.
toml::array replay_numbers(std::span<const double> values);

// Writes `scene` with a comment header (what failed, how to run it: with --scalar when the
// failed run ran on the scalar path) to DIR/replay.toml (or DIR/`name`) and returns the path.
// `outcome` says what the replay shows. Throws std::runtime_error when the file cannot be
// written.
std::filesystem::path write_replay(const std::filesystem::path& dir, const toml::table& scene,
                                   const std::string& what_failed, bool simd,
                                   const std::string& name = replay_file_name,
                                   const std::string& outcome = "fails the same way");

} // namespace ifsim::io
