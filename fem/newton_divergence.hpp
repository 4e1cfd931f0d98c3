#pragma once
// The early cut of SolverSettings::divergence_check: a Newton solve that, 6 iterations in, is
// still above the relative residual it started from has diverged. Such a solve rarely
// recovers within max_iterations, and its iterates are the costliest of a run: their strains
// send the interface models into thousands of substeps (docs/fem.md, "Early cuts").

#include <cstddef>
#include <span>

namespace ifsim::fem {

inline constexpr std::size_t divergence_first_check = 6; // iterations into a solve

// residuals: the relative residuals of the increment so far, one per iteration; the current
// solve started at index `start` (a re-gather of the targets starts a new one).
inline bool newton_diverged(std::span<const double> residuals, std::size_t start) {
    if (residuals.size() < start + divergence_first_check + 1) {
        return false;
    }
    return !(residuals.back() <= residuals[start]); // a NaN counts as diverged
}

} // namespace ifsim::fem
