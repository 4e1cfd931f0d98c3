#include "io/output/progress.hpp"

#include <unistd.h>

#include <string>

#include <fmt/format.h>

namespace ifsim::io {

namespace {

bool is_terminal(std::FILE* f) {
    return isatty(fileno(f)) == 1;
}

} // namespace

ProgressLine::ProgressLine(ProgressMode mode, long total_steps, int stages, std::FILE* out)
    : enabled_(mode == ProgressMode::always ||
               (mode == ProgressMode::automatic && is_terminal(out))),
      quiet_(mode == ProgressMode::never), total_(total_steps), stages_(stages), out_(out),
      start_(Clock::now()) {}

void ProgressLine::update(double step, int stage) {
    update(step, stage, {});
}

void ProgressLine::update(double step, int stage, std::string_view note) {
    if (!enabled_) {
        return;
    }
    const double t = std::chrono::duration<double>(Clock::now() - start_).count();
    if (t < first_after_s || t - last_ < interval_s) {
        return;
    }
    last_ = t;
    shown_ = true;
    const double fraction = total_ > 0 ? step / static_cast<double>(total_) : 1.0;
    // Time left from the pace so far (shown once a percent is done).
    const std::string left = fraction > 0.01 && fraction < 1.0
                                 ? fmt::format("  ~{:.0f} s left", t * (1.0 - fraction) / fraction)
                                 : std::string();
    // Trailing spaces wipe what a longer previous line left behind.
    fmt::print(out_, "\rifsim: step {}/{} ({:.0f}%)  stage {}/{}  {:.1f} s{}{}{}   ",
               static_cast<long>(step), total_, 100.0 * fraction, stage, stages_, t, left,
               note.empty() ? "" : "  ", note);
    std::fflush(out_);
}

void ProgressLine::break_line() {
    if (shown_) {
        fmt::print(out_, "\n");
        std::fflush(out_);
        shown_ = false;
    }
}

void ProgressLine::finish() {
    if (shown_) {
        fmt::print(out_, "\n");
        std::fflush(out_);
        shown_ = false;
    }
    enabled_ = false;
}

} // namespace ifsim::io
