#pragma once
// A run stopped from outside (SIGTERM from a batch system, Ctrl-C, a closed terminal) ends
// like a failed run: the rows so far become history.csv, summary.json says it was
// interrupted, and with checkpoints on, a last checkpoint lets `ifsim resume` go on.
//
// StopSignals installs the handlers for the length of a run; the handler only records the
// signal. The run loops ask stop_signal() after each step (point-level runs) or each Newton
// iteration (boundary-value runs) and throw RunInterrupted. A second signal of the same kind
// ends the process at once (the default action), unless it comes within
// second_signal_delay_ns of the first: that is the same stop delivered twice (coreutils'
// `timeout` signals the process, then its group). A step that does not end soon after the
// signal is covered by StopWatchdog.

#include <chrono>
#include <functional>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>

namespace ifsim::io {

// After a stop signal a run ends within stop_grace or the watchdog ends it (summary.json
// written from what was known before the run). A boundary-value run with checkpoints lets
// the increment under way go on to its checkpoint for at most stop_patience, then gives it
// up and ends through its own path, resumable from the checkpoint before.
inline constexpr std::chrono::milliseconds stop_grace{10'000};
inline constexpr std::chrono::milliseconds stop_patience{5'000};
// A repeat of the first stop signal sooner than this is ignored (one stop, delivered twice).
inline constexpr long long second_signal_delay_ns = 500'000'000;

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

// Whether a run with checkpoints should give up the increment under way: true once a stop
// signal has been pending for `patience` (counted from the first call that saw it), so that
// the run ends through its own path well before the watchdog's grace runs out.
class StopPatience {
public:
    using Clock = std::chrono::steady_clock;
    explicit StopPatience(std::chrono::milliseconds patience = stop_patience)
        : patience_(patience) {}
    bool exhausted(Clock::time_point now = Clock::now()) {
        if (stop_signal() == 0) {
            return false;
        }
        if (!seen_) {
            seen_ = now;
        }
        return now - *seen_ >= patience_;
    }
    std::chrono::milliseconds patience() const { return patience_; }

private:
    std::chrono::milliseconds patience_;
    std::optional<Clock::time_point> seen_;
};

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
