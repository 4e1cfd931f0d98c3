#pragma once
// The queue of a sweep: hands its pending runs to the local run pool and to remote workers (MPI
// ranks) as slots come free, records each run as it ends, prints a line per run, and writes
// DIR/sweep.csv (or sweep.csv.partial when stopped) and DIR/sweep.json. Returns the exit code.

#include <cstddef>
#include <vector>

#include "io/sweep/remote_workers.hpp"
#include "io/sweep/sweep_plan.hpp"

namespace ifsim::io {

struct SweepLayout {
    int local_jobs = 1; // runs at a time in this process
    int threads = 1;    // threads of each run
    int ranks = 1;      // processes of the sweep (MPI ranks; 1 = local)
};

// The default layout of a local sweep with `pending` runs (options --jobs, --threads-per-run).
SweepLayout local_layout(std::size_t pending, const SweepOptions& options);

// Runs the members `pending` of the plan (their records filled in as they end; a line per run
// unless options.quiet) over the local pool and the remote workers. Returns the stop signal that
// ended it early, or 0. Call it with StopSignals installed.
int run_members(SweepPlan& plan, const std::vector<std::size_t>& pending, const SweepLayout& layout,
                const SweepOptions& options, RemoteWorkers* remote);

int coordinate_sweep(const SweepOptions& options, SweepPlan& plan,
                     const std::vector<std::size_t>& pending, std::size_t reused,
                     const SweepLayout& layout, RemoteWorkers* remote);

} // namespace ifsim::io
