#pragma once
// Runs a boundary-value scene with fem's StaticSolver: the mesh, materials and contact pair of
// the scene, its stages in order, one history row per converged increment (and row 0), the
// progress line, and the run's summary (counters, phases, mesh details). A stage that fails
// ends the run with its reason; the rows so far stay in history.csv.

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "engine/failed_contact_point.hpp"
#include "fem/static_solver.hpp"
#include "io/boundary_value/boundary_value_checkpoint.hpp"
#include "io/boundary_value/boundary_value_scene.hpp"
#include "io/output/progress.hpp"
#include "io/output/summary_writer.hpp"

namespace ifsim::io {

struct BoundaryValueRunOutcome {
    bool ok = false;
    std::string reason;
    fem::SolverCounters counters;
    fem::SolverTimers timers;
    double setup_seconds = 0.0;  // solver construction and contact pair, without the K0 stress
    double row_seconds = 0.0;    // rows and progress (inside the stages' time)
    double finish_seconds = 0.0; // closing history.csv
    std::size_t rows = 0;
    long equations = 0;          // of the last stage's DOF map
    std::vector<int> iterations; // Newton iterations of each converged increment
    int nodes = 0, elements = 0;
    fem::InitialImbalance imbalance; // of the initial state under the first stage
    // Field output ([output] fields): files written and the time it took (inside the stages).
    std::size_t field_outputs = 0;
    double field_seconds = 0.0;
    std::vector<std::string> field_collections; // .pvd files relative to DIR
    std::vector<std::string> field_materials;   // names of the cell array `material`
    std::vector<double> field_times_unreached;  // named times after the run's last increment
    nlohmann::ordered_json point_recorders;     // the points the point recorders chose
    long checkpoints = 0;                       // checkpoints written by this run
    double checkpoint_seconds = 0.0;
    // A stage that failed because a contact point failed in Algorithm 1: that call, and its
    // pair's index in scene.contacts (for the replay, io/replay/interface_replay.hpp).
    std::optional<FailedContactPoint> failed_point;
    std::size_t failed_pair = 0;
    // With the iteration log: the costliest Algorithm 1 call of any pair, and that pair's index,
    // written to DIR/costliest-call.toml (the error where it could not be written).
    std::optional<FailedContactPoint> costliest_call;
    std::size_t costliest_pair = 0;
    std::string costliest_call_error;
};

// Checkpoints of a run (--checkpoint-every, --checkpoint-minutes) and a run resumed from one.
struct BoundaryValueCheckpointing : CheckpointRequest {
    const BoundaryValueCheckpoint* resume = nullptr; // continue from this one
};

// Writes DIR/history.csv (and DIR/iterations.csv with `iteration_log`, iteration_log.hpp).
// Throws std::runtime_error only when history.csv cannot be written at all.
BoundaryValueRunOutcome run_boundary_value_scene(const BoundaryValueScene& scene,
                                                 const std::filesystem::path& dir,
                                                 ProgressMode progress, bool simd,
                                                 const BoundaryValueCheckpointing& checkpoints = {},
                                                 bool iteration_log = false);

void add_boundary_value_results(RunSummary& summary, const BoundaryValueScene& scene,
                                const BoundaryValueRunOutcome& run, double parse_s);

} // namespace ifsim::io
