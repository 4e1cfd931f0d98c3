#pragma once
// The runs of a sweep: every combination of its scenes, grid values and zipped values, in a
// fixed order (scene slowest, then the grid keys in file order, the zipped values fastest), each
// identified by the content of its scene file and its overrides, so that running a sweep again
// finds the runs that already finished even when the sweep file was reordered or extended.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "io/sweep/sweep_file.hpp"

namespace ifsim::io {

struct SweepMember {
    std::size_t index = 0;          // 1-based position in the sweep
    std::size_t scene = 0;          // index into SweepFile::scenes
    std::vector<std::string> sets;  // KEY=VALUE: the fixed ones, then the swept ones
    std::vector<std::string> shown; // one per swept key (grid, then zip): the value as shown
    std::string id;                 // 16 hex digits: the folder DIR/runs/<id>
};

// The sweep's swept keys in column order (grid, then zip).
std::vector<std::string> swept_keys(const SweepFile& sweep);

// Expands the sweep into its runs. Reads each scene file for the ids; throws
// std::runtime_error naming a scene file that cannot be read.
std::vector<SweepMember> expand_sweep(const SweepFile& sweep);

// A run's identity: FNV-1a (64 bit) over the scene file's text and the overrides (sorted).
std::string run_id(const std::string& scene_text, const std::vector<std::string>& sets);

} // namespace ifsim::io
