#pragma once
// The replay of a contact point that failed in Algorithm 1 (interface test or contact pair of
// a boundary-value problem): an interface-point scene with the failed call's model, options,
// committed state and inputs, which `ifsim run` evaluates alone.

#include <filesystem>
#include <string>

#include <toml++/toml.h>

#include "engine/failed_contact_point.hpp"
#include "io/scene/material_parameters.hpp"

namespace ifsim::io {

toml::table interface_replay_scene(const FailedContactPoint& point, const MaterialSpec& material,
                                   const std::string& description);

// Writes it to DIR/replay.toml and returns the path; `run_reason` is the failed run's reason.
// Throws std::runtime_error when the call's state or inputs are not finite (cause
// "non-finite input": a scene cannot hold them) or the file cannot be written.
std::filesystem::path write_interface_replay(const std::filesystem::path& dir,
                                             const FailedContactPoint& point,
                                             const MaterialSpec& material,
                                             const std::string& run_reason, bool simd);

// The costliest call of a run (ContactPair::costliest_call, with --iteration-log) to
// DIR/costliest-call.toml: the same scene, described by its cost.
inline constexpr const char* costliest_call_file_name = "costliest-call.toml";
std::filesystem::path write_costliest_call_replay(const std::filesystem::path& dir,
                                                  const FailedContactPoint& point,
                                                  const MaterialSpec& material, bool simd);

} // namespace ifsim::io
