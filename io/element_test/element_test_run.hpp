#pragma once
// Runs an element-test scene with the engine's driver, streaming rows into history.csv and
// showing progress. The row writing happens inside the driver's time; it is measured here so
// the summary can report it as output time.

#include <cstddef>
#include <filesystem>
#include <optional>

#include "engine/element_test_driver.hpp"
#include "engine/state_admissibility.hpp"
#include "io/element_test/element_checkpoint.hpp"
#include "io/element_test/element_test_scene.hpp"
#include "io/output/progress.hpp"

namespace ifsim::io {

struct ElementRunOutcome {
    ElementTestResult result;    // ok = false with a reason also for errors raised while running
    std::size_t rows = 0;        // rows in history.csv
    double row_seconds = 0.0;    // writing rows and progress, inside result.driver_seconds
    double finish_seconds = 0.0; // closing and renaming history.csv
    long checkpoints = 0;        // checkpoints written by this run
    double checkpoint_seconds = 0.0;
    StateAdmissibility admissibility; // rows whose states left the model's sand region
    // The material point failed (not an interruption or a writer error): `last` is the
    // position before the failed step (empty: the first step failed), what a replay needs.
    bool point_failed = false;
    std::optional<ElementTestPosition> last;
};

// Writes DIR/history.csv (kept with the rows so far when the run fails), and DIR/checkpoint
// as asked (removed when the run completes); continues `resume` when given. Throws
// std::runtime_error only when history.csv cannot be written at all.
ElementRunOutcome run_element_test_scene(const ElementTestScene& scene,
                                         const std::filesystem::path& dir, ProgressMode progress,
                                         const CheckpointRequest& checkpoints = {},
                                         const ElementTestCheckpoint* resume = nullptr);

} // namespace ifsim::io
