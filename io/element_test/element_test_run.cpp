#include "io/element_test/element_test_run.hpp"

#include <chrono>
#include <exception>

#include <fmt/format.h>

#include "io/element_test/element_history.hpp"
#include "io/output/history_writer.hpp"
#include "io/output/run_clock.hpp"

namespace ifsim::io {

ElementRunOutcome run_element_test_scene(const ElementTestScene& scene,
                                         const std::filesystem::path& dir, ProgressMode progress,
                                         const CheckpointRequest& checkpoints,
                                         const ElementTestCheckpoint* resume) {
    ElementRunOutcome out;
    HistoryWriter history = open_history(dir, element_history_columns(scene.material.choice),
                                         resume ? &resume->run : nullptr);
    ProgressLine line(progress, scene.total_steps(), static_cast<int>(scene.stages.size()));
    const auto on_row = [&](const ElementRow& row) {
        const auto t0 = Clock::now();
        write_element_row(history, row);
        line.update(row.step, row.stage);
        out.row_seconds += since(t0);
    };
    CheckpointSchedule due(checkpoints);
    const auto on_step = [&](const ElementTestPosition& pos) {
        if (!due.due(pos.step)) {
            return;
        }
        const auto t0 = Clock::now();
        ElementTestCheckpoint c;
        c.run = {"element-test",    checkpoints.scene_text, scene.settings.update.simd,
                 pos.step,          history.sync(),         resume ? resume->run.resumes + 1 : 0,
                 checkpoints.every, checkpoints.minutes};
        c.position = pos;
        write_element_test_checkpoint(dir, c);
        ++out.checkpoints;
        due.written();
        out.checkpoint_seconds += since(t0);
    };
    try {
        out.result = run_element_test(scene.material.choice, scene.initial_state, scene.stages,
                                      scene.settings, on_row, resume ? &resume->position : nullptr,
                                      checkpoints.enabled()
                                          ? std::function<void(const ElementTestPosition&)>(on_step)
                                          : std::function<void(const ElementTestPosition&)>());
    } catch (const std::exception& e) {
        // A writer or engine error in the middle of the run: keep the rows so far.
        out.result.ok = false;
        out.result.reason = fmt::format("run aborted: {}", e.what());
    }
    line.finish();
    if (out.result.ok) {
        remove_checkpoint(dir);
    }
    const auto t1 = Clock::now();
    history.finish();
    out.finish_seconds = since(t1);
    out.rows = history.rows();
    return out;
}

} // namespace ifsim::io
