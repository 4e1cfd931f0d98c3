#pragma once
// The checkpoint of an element-test run (DIR/checkpoint; docs/scenes.md "Checkpoint and
// resume"): the run header and the driver's position after a committed step.

#include <filesystem>

#include "engine/element_test_driver.hpp"
#include "io/output/run_checkpoint.hpp"

namespace ifsim::io {

struct ElementTestCheckpoint {
    RunCheckpointHeader run;
    ElementTestPosition position;
};

// Writes DIR/checkpoint atomically. Throws std::runtime_error naming the file.
void write_element_test_checkpoint(const std::filesystem::path& dir,
                                   const ElementTestCheckpoint& c);
// Reads DIR/checkpoint. Throws CheckpointError naming the file and the defect.
ElementTestCheckpoint read_element_test_checkpoint(const std::filesystem::path& dir);

} // namespace ifsim::io
