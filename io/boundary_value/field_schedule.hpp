#pragma once
// When a boundary-value run writes fields ([output] fields, --fields; docs/scenes.md).

#include <vector>

namespace ifsim::io {

// Every N increments, at the end of every stage, and at the first converged increment at or
// after each named time (the history's time column). The initial state (increment 0) is
// written whenever any of them is on.
struct FieldSchedule {
    long every = 0;
    bool stages = false;
    std::vector<double> times;
    bool enabled() const { return every > 0 || stages || !times.empty(); }
};

} // namespace ifsim::io
