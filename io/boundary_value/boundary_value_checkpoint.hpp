#pragma once
// The checkpoint of a boundary-value run (DIR/checkpoint; docs/scenes.md "Checkpoint and
// resume"): the solver's committed state (fem::SolverSnapshot), where the run stands (stage,
// increment cursor, row count, history.csv.partial's length) and the scene it ran, so that
// `ifsim resume DIR` continues to the same history.csv, byte for byte.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "fem/static_solver.hpp"

namespace ifsim::io {

struct BoundaryValueCheckpoint {
    std::string scene_text;      // DIR/scene.toml as the run started (must match on resume)
    bool simd = true;            // the kernel path (SIMD and scalar differ in round-off)
    std::size_t stage_index = 0; // 0-based stage the cursor is in
    fem::StageCursor cursor;     // where that stage goes on
    long increment = 0;          // rows after row 0
    long steps_before = 0;       // nominal steps of the stages before
    long long history_bytes = 0; // history.csv.partial's length at the checkpoint
    std::vector<int> iterations; // Newton iterations of every increment so far
    long resumes = 0;            // how often this run was resumed already
    long every = 0;              // the run's checkpoint interval (a resumed run keeps it)
    double minutes = 0.0;
    fem::SolverSnapshot snapshot;
};

inline constexpr const char* checkpoint_file_name = "checkpoint";

// Writes DIR/checkpoint atomically. Throws std::runtime_error naming the file.
void write_boundary_value_checkpoint(const std::filesystem::path& dir,
                                     const BoundaryValueCheckpoint& c);
// Reads DIR/checkpoint. Throws CheckpointError naming the file and the defect.
BoundaryValueCheckpoint read_boundary_value_checkpoint(const std::filesystem::path& dir);

} // namespace ifsim::io
