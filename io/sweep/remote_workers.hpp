#pragma once
// Runs handed to other processes of a distributed sweep (the MPI ranks other than 0). The
// coordinator (sweep_command.cpp) fills its own run pool and these workers' free slots from
// one queue, so the table is the same however the runs were spread.

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "io/sweep/child_process.hpp"

namespace ifsim::io {

struct RemoteEnd {
    std::size_t member = 0; // the token given to start()
    ProcessEnd end;         // end.signal < 0: the worker was stopping and did not start the run
    double wall_s = 0.0;
    std::string summary_text; // the run's summary.json ("" when it left none)
    int rank = 0;
};

class RemoteWorkers {
public:
    virtual ~RemoteWorkers() = default;
    // Whether some worker has asked for a run and not yet been given one.
    virtual bool has_free_slot() = 0;
    // Hands a run to a worker that asked: `token` comes back with its end; argv is its command
    // line, run_dir its folder (run.log and summary.json there).
    virtual void start(std::size_t token, const std::vector<std::string>& argv,
                       const std::filesystem::path& run_dir) = 0;
    // A run that a worker reports ended, if any (does not block).
    virtual std::optional<RemoteEnd> poll() = 0;
    // Runs handed out and not yet reported.
    virtual std::size_t outstanding() const = 0;
    // Tells every worker that no more runs come.
    virtual void finish() = 0;
    // Slots over all workers.
    virtual int slots() const = 0;
};

} // namespace ifsim::io
