#include "io/output/run_checkpoint.hpp"

#include <cstdint>
#include <vector>

#include <fmt/format.h>

namespace ifsim::io {

void put_run_header(CheckpointWriter& w, const RunCheckpointHeader& h) {
    w.put("kind", h.kind);
    w.put("scene", h.scene_text);
    w.put("run", std::vector<std::int64_t>{h.simd ? 1 : 0, h.increment, h.history_bytes, h.resumes,
                                           h.every});
    w.put("minutes", std::vector<double>{h.minutes});
}

RunCheckpointHeader read_run_header(const CheckpointReader& r, const std::filesystem::path& file,
                                    const std::string& kind) {
    RunCheckpointHeader h;
    h.kind = r.text("kind");
    if (!kind.empty() && h.kind != kind) {
        throw CheckpointError(fmt::format("{}: a checkpoint of a {} run, not of a {} run",
                                          file.string(), h.kind, kind));
    }
    h.scene_text = r.text("scene");
    const auto run = r.integers("run");
    if (run.size() != 5) {
        throw CheckpointError(fmt::format("{}: malformed run section", file.string()));
    }
    h.simd = run[0] != 0;
    h.increment = run[1];
    h.history_bytes = run[2];
    h.resumes = run[3];
    h.every = run[4];
    h.minutes = r.real("minutes");
    if (h.increment < 0 || h.history_bytes < 0 || h.resumes < 0 || h.every < 0 ||
        !(h.minutes >= 0.0)) {
        throw CheckpointError(fmt::format("{}: malformed run section", file.string()));
    }
    return h;
}

HistoryWriter open_history(const std::filesystem::path& dir, std::vector<std::string> columns,
                           const RunCheckpointHeader* resumed) {
    if (!resumed) {
        return HistoryWriter(dir, std::move(columns));
    }
    return HistoryWriter(
        dir, std::move(columns),
        {resumed->history_bytes, static_cast<std::size_t>(resumed->increment) + 1});
}

void remove_checkpoint(const std::filesystem::path& dir) {
    std::error_code ignored; // a missing checkpoint is as good as a removed one
    std::filesystem::remove(dir / checkpoint_file_name, ignored);
}

std::string checkpoint_kind(const std::filesystem::path& dir) {
    return CheckpointReader(dir / checkpoint_file_name).text("kind");
}

} // namespace ifsim::io
