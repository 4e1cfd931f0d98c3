#pragma once
// Runs an interface-point scene: the one Algorithm 1 call, on the SIMD or scalar path, with
// history.csv (row 0 the state before, row 1 after a successful call) and the summary.

#include <cstddef>
#include <filesystem>
#include <string>

#include "engine/failed_contact_point.hpp"
#include "io/interface_point/interface_point_scene.hpp"
#include "io/output/summary_writer.hpp"

namespace ifsim::io {

struct InterfacePointOutcome {
    bool ok = false;
    std::string reason; // the failure in words (describe_interface_failure)
    ContactPointOutcome call;
    double seconds = 0.0;
    std::size_t rows = 0;
};

// Writes DIR/history.csv. Throws std::runtime_error when it cannot be written.
InterfacePointOutcome run_interface_point_scene(const InterfacePointScene& scene,
                                                const std::filesystem::path& dir, bool simd);

// Status, reason, counters, the call's traction and the timing phases.
void add_interface_point_results(RunSummary& summary, const InterfacePointScene& scene,
                                 const InterfacePointOutcome& run, double parse_s);

} // namespace ifsim::io
