#include "io/output/stop_signal.hpp"

#include <atomic>
#include <csignal>
#include <cstdint>
#include <cstdlib>
#include <ctime>

#include <fmt/format.h>

namespace ifsim::io {

namespace {

volatile std::sig_atomic_t received = 0;
// When the first signal arrived (CLOCK_MONOTONIC, ns; a lock-free atomic, safe in a handler).
std::atomic<std::int64_t> received_at{0};
static_assert(std::atomic<std::int64_t>::is_always_lock_free);
constexpr int handled[] = {SIGTERM, SIGINT, SIGHUP};
struct sigaction previous[std::size(handled)];

std::int64_t monotonic_ns() {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts); // async-signal-safe (POSIX)
    return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

extern "C" void on_stop_signal(int sig) {
    const std::int64_t now = monotonic_ns();
    if (received == sig) {
        // One stop delivered twice: coreutils' `timeout` signals the process and then its
        // process group, as some batch systems do; both arrive within microseconds.
        if (now - received_at.load() < second_signal_delay_ns) {
            return;
        }
        // The second time: the user means it. Default action, now.
        std::signal(sig, SIG_DFL);
        std::raise(sig);
        return;
    }
    if (received == 0) {
        received_at.store(now);
        received = sig;
    }
}

} // namespace

int stop_signal() {
    return received;
}

std::string signal_name(int signal) {
    switch (signal) {
    case SIGTERM:
        return "SIGTERM";
    case SIGINT:
        return "SIGINT";
    case SIGHUP:
        return "SIGHUP";
    default:
        return fmt::format("signal {}", signal);
    }
}

StopSignals::StopSignals() {
    received = 0;
    struct sigaction action {};
    action.sa_handler = &on_stop_signal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;
    for (std::size_t i = 0; i < std::size(handled); ++i) {
        sigaction(handled[i], &action, &previous[i]);
    }
}

StopSignals::~StopSignals() {
    for (std::size_t i = 0; i < std::size(handled); ++i) {
        sigaction(handled[i], &previous[i], nullptr);
    }
}

void throw_if_stopped(const std::string& done, bool resumable) {
    const int sig = stop_signal();
    if (sig == 0) {
        return;
    }
    throw RunInterrupted(
        sig,
        fmt::format("interrupted by {} after {}{}", signal_name(sig), done,
                    resumable ? " (checkpoint written: `ifsim resume DIR` goes on from it)" : ""));
}

StopWatchdog::StopWatchdog(std::chrono::milliseconds grace, std::function<void(int)> last_word)
    : grace_(grace), last_word_(std::move(last_word)), thread_([this] { watch(); }) {}

StopWatchdog::~StopWatchdog() {
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
    }
    thread_.join();
}

bool StopWatchdog::disarm() {
    std::lock_guard lock(mutex_);
    const bool was = armed_;
    armed_ = false;
    return was;
}

void StopWatchdog::watch() {
    using Clock = std::chrono::steady_clock;
    constexpr auto poll = std::chrono::milliseconds(50);
    Clock::time_point seen{};
    for (;;) {
        {
            std::lock_guard lock(mutex_);
            if (stop_ || !armed_) {
                return;
            }
        }
        const int sig = stop_signal();
        if (sig != 0) {
            if (seen == Clock::time_point{}) {
                seen = Clock::now();
            } else if (Clock::now() - seen >= grace_) {
                std::lock_guard lock(mutex_);
                if (!armed_ || stop_) {
                    return;
                }
                armed_ = false;
                last_word_(sig);
                std::_Exit(interrupted_exit_code(sig));
            }
        }
        std::this_thread::sleep_for(poll);
    }
}

} // namespace ifsim::io
