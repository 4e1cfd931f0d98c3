#pragma once
// One progress line on stderr for runs longer than about a second: step/total, stage and
// elapsed time, rewritten in place (carriage return) at most five times per second. Shown
// automatically when stderr is a terminal, always with --progress, never with --quiet.

#include <chrono>
#include <cstdio>
#include <string_view>

namespace ifsim::io {

enum class ProgressMode { automatic, always, never };

class ProgressLine {
public:
    ProgressLine(ProgressMode mode, long total_steps, int stages, std::FILE* out = stderr);
    ~ProgressLine() { finish(); }
    ProgressLine(const ProgressLine&) = delete;
    ProgressLine& operator=(const ProgressLine&) = delete;

    // step may be fractional (a step part-way done); the line shows the estimated time left.
    void update(double step, int stage);
    // The same with a run-specific note after the time ("Newton 3, residual 1.2e-09").
    void update(double step, int stage, std::string_view note);
    // Ends the line (newline) if one was shown.
    void finish();

    bool enabled() const { return enabled_; }
    bool quiet() const { return quiet_; } // --quiet: no warnings on the console either
    // Ends a shown line (newline) so that a message can follow; the line goes on below it.
    void break_line();
    bool shown() const { return shown_; }

    static constexpr double first_after_s = 1.0;
    static constexpr double interval_s = 0.2;

private:
    using Clock = std::chrono::steady_clock;
    bool enabled_;
    bool quiet_;
    long total_;
    int stages_;
    std::FILE* out_;
    Clock::time_point start_;
    double last_ = -1.0;
    bool shown_ = false;
};

} // namespace ifsim::io
