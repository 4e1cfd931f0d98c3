#pragma once
// The checkpoint of an interface-test run (DIR/checkpoint; docs/scenes.md "Checkpoint and
// resume"): the run header and the driver's position after a committed step.

#include <filesystem>

#include "engine/interface_test_driver.hpp"
#include "io/output/run_checkpoint.hpp"

namespace ifsim::io {

struct InterfaceTestCheckpoint {
    RunCheckpointHeader run;
    InterfaceTestPosition position;
};

// Writes DIR/checkpoint atomically. Throws std::runtime_error naming the file.
void write_interface_test_checkpoint(const std::filesystem::path& dir,
                                     const InterfaceTestCheckpoint& c);
// Reads DIR/checkpoint. Throws CheckpointError naming the file and the defect.
InterfaceTestCheckpoint read_interface_test_checkpoint(const std::filesystem::path& dir);

} // namespace ifsim::io
