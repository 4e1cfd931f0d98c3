#pragma once
// Wall-clock helpers of the run drivers: seconds since a time point, counters rounded for
// summary.json.

#include <chrono>
#include <cmath>

namespace ifsim::io {

using Clock = std::chrono::steady_clock;

inline double since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

inline long long rounded(double x) {
    return static_cast<long long>(std::llround(x));
}

} // namespace ifsim::io
