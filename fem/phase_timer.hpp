#pragma once
// Adds the wall time of a scope to a phase's seconds (the solver's and the contact pairs'
// timers, summary.json's phases).

#include <chrono>

namespace ifsim::fem {

class PhaseTimer {
public:
    explicit PhaseTimer(double& sink) : sink_(sink), t0_(Clock::now()) {}
    ~PhaseTimer() { sink_ += std::chrono::duration<double>(Clock::now() - t0_).count(); }
    PhaseTimer(const PhaseTimer&) = delete;
    PhaseTimer& operator=(const PhaseTimer&) = delete;

private:
    using Clock = std::chrono::steady_clock;
    double& sink_;
    Clock::time_point t0_;
};

} // namespace ifsim::fem
