#include "io/element_test/element_test_run.hpp"

#include <chrono>
#include <exception>

#include <fmt/format.h>

#include "io/element_test/element_history.hpp"
#include "io/output/history_writer.hpp"
#include "io/output/run_clock.hpp"
#include "io/output/step_checkpoints.hpp"
#include "io/output/stop_signal.hpp"

namespace ifsim::io {

ElementRunOutcome run_element_test_scene(const ElementTestScene& scene,
                                         const std::filesystem::path& dir, ProgressMode progress,
                                         const CheckpointRequest& checkpoints,
                                         const ElementTestCheckpoint* resume) {
    ElementRunOutcome out;
    HistoryWriter history = open_history(dir, element_history_columns(scene.material.choice),
                                         resume ? &resume->run : nullptr);
    ProgressLine line(progress, scene.total_steps(), static_cast<int>(scene.stages.size()));
    const int reported = reported_state_size(scene.material.choice);
    const auto on_row = [&](const ElementRow& row) {
        const auto t0 = Clock::now();
        write_element_row(history, row, reported);
        check_state(scene.material.choice, row.state.data(), row.step, out.admissibility);
        line.update(row.step, row.stage);
        out.row_seconds += since(t0);
        if (!checkpoints.enabled()) { // else StepCheckpoints writes one first
            throw_if_stopped(fmt::format("step {} of {}", row.step, scene.total_steps()), false);
        }
    };
    StepCheckpoints<ElementTestCheckpoint, ElementTestPosition> saved(
        checkpoints, "element-test", scene.settings.update.simd, resume, history, dir,
        &write_element_test_checkpoint, scene.total_steps());
    if (resume) {
        out.last = resume->position;
    }
    // Every committed position is kept for a replay of a step that fails.
    const auto on_step = [&, save = saved.callback()](const ElementTestPosition& p) {
        out.last = p;
        if (save) {
            save(p);
        }
    };
    try {
        out.result =
            run_element_test(scene.material.choice, scene.initial_state, scene.stages,
                             scene.settings, on_row, resume ? &resume->position : nullptr, on_step);
        out.point_failed = !out.result.ok;
    } catch (const RunInterrupted& e) {
        out.result.ok = false;
        out.result.reason = e.what();
    } catch (const std::exception& e) {
        // A writer or engine error in the middle of the run: keep the rows so far.
        out.result.ok = false;
        out.result.reason = fmt::format("run aborted: {}", e.what());
    }
    line.finish();
    out.checkpoints = saved.written();
    out.checkpoint_seconds = saved.seconds();
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
