#pragma once
// `mpirun -np N ifsim sweep ...`: the sweep spread over MPI ranks (Open MPI). Rank 0 reads the
// sweep, runs its share and hands out the others' runs as ranks come free; every rank runs its
// runs as child processes like the local sweep; rank 0 writes the same sweep.csv (rows in sweep
// order) and sweep.json. DIR must be on a file system all ranks see.

#include <functional>

#include "io/sweep/remote_workers.hpp"
#include "io/sweep/sweep_command.hpp"
#include "io/sweep/sweep_coordinator.hpp"

namespace ifsim::io {

// Whether this process was started by an MPI launcher (mpirun, mpiexec, srun --mpi=pmix).
bool launched_by_mpi();

// One rank of an MPI job: rank 0 calls `coordinate` with the other ranks as remote workers
// (they run what it hands out until it returns) and the layout (ranks; jobs per rank from
// --jobs, default 1; threads per run from --threads-per-run, default the node's cores shared
// out). Returns the exit code: rank 0's from `coordinate`, a worker's own. Without MPI support
// in this build: an error (exit 2) rather than N ranks each doing the whole work into one folder.
int run_on_mpi_ranks(const SweepOptions& options,
                     const std::function<int(const SweepLayout&, RemoteWorkers&)>& coordinate);

} // namespace ifsim::io
