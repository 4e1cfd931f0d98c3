#pragma once
// The checkpoint of a boundary-value run (DIR/checkpoint; docs/scenes.md "Checkpoint and
// resume"): the solver's committed state (fem::SolverSnapshot), where the run stands (stage,
// increment cursor, row count, history.csv.partial's length) and the scene it ran, so that
// `ifsim resume DIR` continues to the same history.csv, byte for byte.

#include <cstdint>
#include <filesystem>
#include <vector>

#include "fem/static_solver.hpp"
#include "io/boundary_value/boundary_value_fields.hpp"
#include "io/output/run_checkpoint.hpp"

namespace ifsim::io {

struct BoundaryValueCheckpoint {
    RunCheckpointHeader run;     // scene, kernel path, rows, history length, interval
    std::size_t stage_index = 0; // 0-based stage the cursor is in
    fem::StageCursor cursor;     // where that stage goes on
    long steps_before = 0;       // nominal steps of the stages before
    std::vector<int> iterations; // Newton iterations of every increment so far
    fem::SolverSnapshot snapshot;
    FieldOutputState fields; // the field collections so far (a run with fields)
};

// Writes DIR/checkpoint atomically. Throws std::runtime_error naming the file.
void write_boundary_value_checkpoint(const std::filesystem::path& dir,
                                     const BoundaryValueCheckpoint& c);
// Reads DIR/checkpoint. Throws CheckpointError naming the file and the defect.
BoundaryValueCheckpoint read_boundary_value_checkpoint(const std::filesystem::path& dir);

} // namespace ifsim::io
