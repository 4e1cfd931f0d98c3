#pragma once
// A run stopped from outside (SIGTERM from a batch system, Ctrl-C, a closed terminal) ends
// like a failed run: the rows so far become history.csv, summary.json says it was
// interrupted, and with checkpoints on, a last checkpoint lets `ifsim resume` go on.
//
// StopSignals installs the handlers for the length of a run; the handler only records the
// signal. The run loops ask stop_signal() after each step (point-level runs) or each Newton
// iteration (boundary-value runs) and throw RunInterrupted. A second signal of the same kind
// ends the process at once (the default action). A step that does not end soon after the
// signal is covered by StopWatchdog.

#include <chrono>
#include <functional>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>

namespace ifsim::io {

// 0, or the number of the first stop signal received since StopSignals was installed.
int stop_signal();
// "SIGTERM", "SIGINT", "SIGHUP" (or "signal N").
std::string signal_name(int signal);

class StopSignals {
public:
    StopSignals();
    ~StopSignals();
    StopSignals(const StopSignals&) = delete;
    StopSignals& operator=(const StopSignals&) = delete;
};

class RunInterrupted : public std::runtime_error {
public:
    RunInterrupted(int signal, const std::string& what)
        : std::runtime_error(what), signal_(signal) {}
    int signal() const { return signal_; }

private:
    int signal_;
};

// Throws RunInterrupted when a stop signal has arrived: "interrupted by SIGTERM after
// <done>", e.g. done = "step 17 of 800". `resumable`: a checkpoint of that point was written.
void throw_if_stopped(const std::string& done, bool resumable);

// The shell's exit status of a process ended by `signal` (128 + N).
inline int interrupted_exit_code(int signal) {
    return 128 + signal;
}

// Ends a run whose step does not return after a stop signal: after `grace` it calls `last_word`
// (writes summary.json) and ends the process with interrupted_exit_code. The run's own ending
// calls disarm() first; the two never both write (one mutex).
class StopWatchdog {
public:
    StopWatchdog(std::chrono::milliseconds grace, std::function<void(int signal)> last_word);
    ~StopWatchdog();
    StopWatchdog(const StopWatchdog&) = delete;
    StopWatchdog& operator=(const StopWatchdog&) = delete;
    // After this the watchdog does nothing; returns false when it has already taken over.
    bool disarm();

private:
    void watch();
    std::chrono::milliseconds grace_;
    std::function<void(int)> last_word_;
    std::mutex mutex_;
    bool armed_ = true;
    bool stop_ = false;
    std::thread thread_;
};

} // namespace ifsim::io
