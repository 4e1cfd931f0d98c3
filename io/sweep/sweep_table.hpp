#pragma once
// sweep.csv: one row per run of a sweep, in the sweep's order: run (1-based), id, scene, one
// column per swept key (named by the key), status (ok | failed | not_run), reason, wall_s,
// then the run's scalar results (summary.json "results", the union over all runs in order of
// first appearance) and its counters increments and newton_iterations. Cells a run does not
// have are empty.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/sweep/sweep_file.hpp"
#include "io/sweep/sweep_members.hpp"

namespace ifsim::io {

// What a finished run left in its folder.
struct RunRecord {
    bool ok = false;
    std::string reason;
    double wall_s = 0.0;
    std::string path; // "simd" | "scalar": the kernel path it ran on
    nlohmann::ordered_json results = nlohmann::ordered_json::object();
    nlohmann::ordered_json counters = nlohmann::ordered_json::object();
};

// The record in DIR/runs/<id>/summary.json, or nullopt when the folder has no readable summary
// (never run, or killed before it wrote one).
std::optional<RunRecord> read_run_record(const std::filesystem::path& run_dir);

// The record of a summary.json's text (nullopt when it is not a run summary).
std::optional<RunRecord> run_record_from_text(const std::string& summary_text);

// A failed record for a run that left no summary: `reason` says how it ended.
RunRecord failed_record(std::string reason);

// The text of sweep.csv. records[i] belongs to members[i]; nullopt = not run (yet).
std::string sweep_csv(const SweepFile& sweep, const std::vector<SweepMember>& members,
                      const std::vector<std::optional<RunRecord>>& records);

// One CSV field, quoted when it holds a comma, a quote or a line break.
std::string csv_field(const std::string& text);

} // namespace ifsim::io
