#pragma once
// Runs an interface-test scene with the engine's driver (engine/interface_test_driver.hpp),
// streaming rows into history.csv and showing progress, and fills the run's summary. Writing rows
// happens inside the driver's time; it is measured here so the summary reports it as output time.

#include <cstddef>
#include <filesystem>

#include "engine/interface_test_driver.hpp"
#include "engine/state_admissibility.hpp"
#include "io/interface_test/interface_checkpoint.hpp"
#include "io/interface_test/interface_test_scene.hpp"
#include "io/output/progress.hpp"
#include "io/output/summary_writer.hpp"

namespace ifsim::io {

struct InterfaceRunOutcome {
    InterfaceTestResult result;  // ok = false with a reason also for errors raised while running
    std::size_t rows = 0;        // rows in history.csv
    double row_seconds = 0.0;    // writing rows and progress, inside result.driver_seconds
    double finish_seconds = 0.0; // closing and renaming history.csv
    long checkpoints = 0;        // checkpoints written by this run
    double checkpoint_seconds = 0.0;
    StateAdmissibility admissibility;        // the interface band's states (continuum models)
    StateAdmissibility sample_admissibility; // the sample's
};

// Writes DIR/history.csv (kept with the rows so far when the run fails), and DIR/checkpoint
// as asked (removed when the run completes); continues `resume` when given. Throws
// std::runtime_error only when history.csv cannot be written at all.
InterfaceRunOutcome run_interface_test_scene(const InterfaceTestScene& scene,
                                             const std::filesystem::path& dir,
                                             ProgressMode progress,
                                             const CheckpointRequest& checkpoints = {},
                                             const InterfaceTestCheckpoint* resume = nullptr);

// Status, counters, timing phases (parse, interface, sample, driver, output) and the scene's
// settings of a finished (or failed) run.
void add_interface_test_results(RunSummary& summary, const InterfaceTestScene& scene,
                                const InterfaceRunOutcome& run, double parse_s);

} // namespace ifsim::io
