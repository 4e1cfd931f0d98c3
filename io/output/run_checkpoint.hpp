#pragma once
// What every scene kind's checkpoint says about its run (DIR/checkpoint; docs/scenes.md
// "Checkpoint and resume"): the kind, the scene it ran, the kernel path, how far history.csv
// had got, and the run's checkpoint interval; plus when a run writes the next checkpoint.
// The kinds add their own sections (boundary_value_checkpoint, element_checkpoint,
// interface_checkpoint).

#include <filesystem>
#include <string>
#include <vector>

#include "io/output/checkpoint_file.hpp"
#include "io/output/history_writer.hpp"
#include "io/output/run_clock.hpp"

namespace ifsim::io {

inline constexpr const char* checkpoint_file_name = "checkpoint";

struct RunCheckpointHeader {
    std::string kind;            // the scene kind ("element-test", ...)
    std::string scene_text;      // DIR/scene.toml as the run started (must match on resume)
    bool simd = true;            // the kernel path (SIMD and scalar differ in round-off)
    long increment = 0;          // history rows after row 0
    long long history_bytes = 0; // history.csv.partial's length at the checkpoint
    long resumes = 0;            // how often this run was resumed already
    long every = 0;              // the run's checkpoint interval (a resumed run keeps it)
    double minutes = 0.0;
};

void put_run_header(CheckpointWriter& w, const RunCheckpointHeader& h);
// Reads the header of DIR/checkpoint's reader; `kind` must match the reader's kind section
// (empty: any). Throws CheckpointError naming the file and the defect.
RunCheckpointHeader read_run_header(const CheckpointReader& r, const std::filesystem::path& file,
                                    const std::string& kind = {});
// The kind of the checkpoint in DIR (reads and checks the whole file).
std::string checkpoint_kind(const std::filesystem::path& dir);

// DIR/history.csv.partial of a new run, or of a resumed one cut back to where its checkpoint
// left it.
HistoryWriter open_history(const std::filesystem::path& dir, std::vector<std::string> columns,
                           const RunCheckpointHeader* resumed);
// Removes DIR/checkpoint of a run that is complete (nothing is left to resume).
void remove_checkpoint(const std::filesystem::path& dir);

// Checkpoints a run was asked for (--checkpoint-every N, --checkpoint-minutes M).
struct CheckpointRequest {
    long every = 0;         // increments between checkpoints (0: none by count)
    double minutes = 0.0;   // wall-clock minutes between checkpoints (0: none by time)
    std::string scene_text; // DIR/scene.toml, stored in the checkpoint
    bool enabled() const { return every > 0 || minutes > 0.0; }
};

// Whether a checkpoint is due after an increment: every N increments or M minutes after the
// last one (or the run's start).
class CheckpointSchedule {
public:
    explicit CheckpointSchedule(const CheckpointRequest& r)
        : every_(r.every), minutes_(r.minutes), last_(Clock::now()) {}
    bool due(long increment) const {
        return (every_ > 0 && increment % every_ == 0) ||
               (minutes_ > 0.0 && since(last_) >= 60.0 * minutes_);
    }
    void written() { last_ = Clock::now(); }

private:
    long every_;
    double minutes_;
    Clock::time_point last_;
};

} // namespace ifsim::io
