#pragma once
// The checkpoints of a point-level run (element test, interface test): after each step the
// driver reports its position; when a checkpoint is due (every N steps or M minutes) the
// history so far is synced and the position written with the run header. A stop signal makes
// one due at once, and the run then ends (RunInterrupted) resumable from it.

#include <filesystem>
#include <functional>

#include <fmt/format.h>

#include "io/output/history_writer.hpp"
#include "io/output/run_checkpoint.hpp"
#include "io/output/stop_signal.hpp"

namespace ifsim::io {

// Checkpoint: a struct with `RunCheckpointHeader run` and `Position position`.
template <class Checkpoint, class Position>
class StepCheckpoints {
public:
    using Write = void (*)(const std::filesystem::path&, const Checkpoint&);

    StepCheckpoints(const CheckpointRequest& request, const char* kind, bool simd,
                    const Checkpoint* resumed, HistoryWriter& history,
                    const std::filesystem::path& dir, Write write, long total_steps)
        : request_(request), kind_(kind), simd_(simd), resumed_(resumed), history_(history),
          dir_(dir), write_(write), due_(request), total_(total_steps) {}

    // The driver's per-step callback (empty when no checkpoints are asked for: the driver then
    // builds no positions).
    std::function<void(const Position&)> callback() {
        if (!request_.enabled()) {
            return {};
        }
        return [this](const Position& p) { after_step(p); };
    }
    long written() const { return written_; }
    double seconds() const { return seconds_; }

private:
    void after_step(const Position& p) {
        const bool stop = stop_signal() != 0;
        if (!due_.due(p.step) && !stop) {
            return;
        }
        const auto t0 = Clock::now();
        Checkpoint c;
        c.run = {kind_,          request_.scene_text, simd_,
                 p.step,         history_.sync(),     resumed_ ? resumed_->run.resumes + 1 : 0,
                 request_.every, request_.minutes};
        c.position = p;
        write_(dir_, c);
        ++written_;
        due_.written();
        seconds_ += since(t0);
        if (stop) {
            throw_if_stopped(fmt::format("step {} of {}", p.step, total_), true);
        }
    }

    const CheckpointRequest& request_;
    const char* kind_;
    bool simd_;
    const Checkpoint* resumed_;
    HistoryWriter& history_;
    std::filesystem::path dir_;
    Write write_;
    CheckpointSchedule due_;
    long written_ = 0;
    double seconds_ = 0.0;
    long total_;
};

} // namespace ifsim::io
