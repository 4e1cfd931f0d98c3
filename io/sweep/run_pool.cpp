#include "io/sweep/run_pool.hpp"

#include <signal.h>
#include <sys/wait.h>

namespace ifsim::io {

RunPool::RunPool(int capacity) : capacity_(capacity) {
    reap_own_children();
}

RunPool::~RunPool() {
    stop_all();
    for (const auto& [pid, run] : running_) {
        int status = 0;
        ::waitpid(pid, &status, 0);
    }
}

void RunPool::start(std::size_t member, const std::vector<std::string>& argv,
                    const std::filesystem::path& log) {
    const pid_t pid = start_process(argv, log);
    running_[pid] = {member, Clock::now()};
}

std::optional<RunPool::Ended> RunPool::poll() {
    for (auto it = running_.begin(); it != running_.end(); ++it) {
        const std::optional<ProcessEnd> end = child_ended(it->first);
        if (end) {
            Ended e{it->second.member, *end,
                    std::chrono::duration<double>(Clock::now() - it->second.started).count()};
            running_.erase(it);
            return e;
        }
    }
    return std::nullopt;
}

void RunPool::stop_all() {
    // SIGHUP: each run ends as on any stop signal (summary "interrupted", rows kept). Not the
    // sweep's own signal: a batch system's SIGTERM may reach the runs directly as well, and a
    // second signal of one kind ends a run at once, without its summary.
    for (const auto& [pid, run] : running_) {
        ::kill(pid, SIGHUP);
    }
}

} // namespace ifsim::io
