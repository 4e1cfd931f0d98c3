#pragma once
// The Euclidean norm of a vector of the solver (residuals, increments, force levels).

#include <cmath>
#include <span>

namespace ifsim::fem {

inline double norm2(std::span<const double> v) {
    double s = 0.0;
    for (double x : v) {
        s += x * x;
    }
    return std::sqrt(s);
}

} // namespace ifsim::fem
