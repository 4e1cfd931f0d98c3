#pragma once
// The runs of a sweep going on in this process's care: up to `capacity` child processes
// (`ifsim run ...`), started, polled and, on a stop signal, asked to stop.

#include <sys/types.h>

#include <chrono>
#include <cstddef>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "io/sweep/child_process.hpp"

namespace ifsim::io {

class RunPool {
public:
    explicit RunPool(int capacity);
    ~RunPool(); // stops and waits for runs still going (an error path)
    RunPool(const RunPool&) = delete;
    RunPool& operator=(const RunPool&) = delete;

    bool has_free_slot() const { return static_cast<int>(running_.size()) < capacity_; }
    bool empty() const { return running_.empty(); }
    int capacity() const { return capacity_; }

    // Starts member `member` as argv with its console output in `log`. Throws
    // std::runtime_error when it cannot be started.
    void start(std::size_t member, const std::vector<std::string>& argv,
               const std::filesystem::path& log);

    struct Ended {
        std::size_t member = 0;
        ProcessEnd end;
        double wall_s = 0.0;
    };
    // A run that has ended, if one has (does not block).
    std::optional<Ended> poll();

    // A stop (SIGHUP) to every run going on: each writes its summary (interrupted) and ends.
    void stop_all();

private:
    using Clock = std::chrono::steady_clock;
    struct Running {
        std::size_t member;
        Clock::time_point started;
    };
    int capacity_;
    std::map<pid_t, Running> running_;
};

} // namespace ifsim::io
