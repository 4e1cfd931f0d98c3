#include "io/progress.hpp"

#include <unistd.h>

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
      total_(total_steps), stages_(stages), out_(out), start_(Clock::now()) {}

void ProgressLine::update(long step, int stage) {
    update(step, stage, {});
}

void ProgressLine::update(long step, int stage, std::string_view note) {
    if (!enabled_) {
        return;
    }
    const double t = std::chrono::duration<double>(Clock::now() - start_).count();
    if (t < first_after_s || t - last_ < interval_s) {
        return;
    }
    last_ = t;
    shown_ = true;
    const double percent = total_ > 0 ? 100.0 * static_cast<double>(step) / total_ : 100.0;
    // Trailing spaces wipe what a longer previous line left behind.
    fmt::print(out_, "\rifsim: step {}/{} ({:.0f}%)  stage {}/{}  {:.1f} s{}{}   ", step, total_,
               percent, stage, stages_, t, note.empty() ? "" : "  ", note);
    std::fflush(out_);
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
