#pragma once
// summary.json of a run (scene-format.md): scene, kind, status ("ok" | "failed" with a
// reason), quality ("clean" | "degraded", with warnings), threads, revision, timing {wall_s,
// phases}, counters, plus run details. Written last and atomically: DIR/summary.json.tmp, then
// renamed to DIR/summary.json, so a run that died never leaves a summary saying "ok".

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace ifsim::io {

// A result that rests on something other than the stated equations (a clamped shear band,
// relaxed interface targets, a safeguard of a material update): the run is "ok" but
// "degraded", and says so loudly.
struct RunWarning {
    std::string code;    // e.g. "band_clamped"
    double count = 0.0;  // how often
    std::string message; // what it means for the results
};

struct RunSummary {
    std::string scene; // the scene file as given on the command line
    std::string kind;  // empty when the scene could not be read that far (written as null)
    bool ok = false;
    std::string reason; // why the run failed
    int threads = 1;
    double wall_s = 0.0;
    std::vector<std::pair<std::string, double>> phases; // seconds per phase, in run order
    nlohmann::ordered_json counters = nlohmann::ordered_json::object();
    nlohmann::ordered_json details = nlohmann::ordered_json::object(); // merged into the top level
    std::vector<RunWarning> warnings; // a successful run with any is "quality": "degraded"
};

// The git revision and version this binary was built from.
const char* build_revision();
const char* build_version();

nlohmann::ordered_json summary_json(const RunSummary& summary);

// Writes DIR/summary.json atomically. Throws std::runtime_error naming the file on I/O errors.
void write_summary(const std::filesystem::path& dir, const RunSummary& summary);

inline constexpr const char* summary_file_name = "summary.json";
inline constexpr const char* summary_temp_name = "summary.json.tmp";

} // namespace ifsim::io
