#include "io/sweep/sweep_table.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

namespace ifsim::io {

namespace {

// The counters every scene kind reports, as columns after the results.
constexpr const char* counter_columns[] = {"increments", "newton_iterations"};

std::string number_cell(const nlohmann::ordered_json& value) {
    if (value.is_number_integer()) {
        return fmt::format("{}", value.get<long long>());
    }
    if (value.is_number()) {
        return fmt::format("{}", value.get<double>());
    }
    if (value.is_boolean()) {
        return value.get<bool>() ? "true" : "false";
    }
    return "";
}

} // namespace

std::string csv_field(const std::string& text) {
    if (text.find_first_of(",\"\n\r") == std::string::npos) {
        return text;
    }
    std::string out = "\"";
    for (const char c : text) {
        out += c == '"' ? std::string("\"\"") : std::string(1, c);
    }
    return out + "\"";
}

std::optional<RunRecord> read_run_record(const std::filesystem::path& run_dir) {
    std::ifstream in(run_dir / "summary.json");
    if (!in) {
        return std::nullopt;
    }
    std::ostringstream text;
    text << in.rdbuf();
    return run_record_from_text(text.str());
}

std::optional<RunRecord> run_record_from_text(const std::string& summary_text) {
    const nlohmann::ordered_json s = nlohmann::ordered_json::parse(summary_text, nullptr, false);
    if (s.is_discarded() || !s.is_object() || !s.contains("status")) {
        return std::nullopt;
    }
    RunRecord r;
    r.ok = s["status"] == "ok";
    if (s.contains("reason") && s["reason"].is_string()) {
        r.reason = s["reason"].get<std::string>();
    }
    if (s.contains("timing") && s["timing"].contains("wall_s")) {
        r.wall_s = s["timing"]["wall_s"].get<double>();
    }
    if (s.contains("path") && s["path"].is_string()) {
        r.path = s["path"].get<std::string>();
    }
    if (s.contains("results") && s["results"].is_object()) {
        r.results = s["results"];
    }
    if (s.contains("counters") && s["counters"].is_object()) {
        r.counters = s["counters"];
    }
    return r;
}

RunRecord failed_record(std::string reason) {
    RunRecord r;
    r.reason = std::move(reason);
    return r;
}

std::string sweep_csv(const SweepFile& sweep, const std::vector<SweepMember>& members,
                      const std::vector<std::optional<RunRecord>>& records) {
    std::vector<std::string> result_names;
    for (const auto& r : records) {
        if (!r) {
            continue;
        }
        for (const auto& [name, value] : r->results.items()) {
            if (std::find(result_names.begin(), result_names.end(), name) == result_names.end()) {
                result_names.push_back(name);
            }
        }
    }
    std::vector<std::string> head = {"run", "id", "scene"};
    for (const std::string& k : swept_keys(sweep)) {
        head.push_back(k);
    }
    for (const char* c : {"status", "reason", "wall_s"}) {
        head.emplace_back(c);
    }
    head.insert(head.end(), result_names.begin(), result_names.end());
    head.insert(head.end(), std::begin(counter_columns), std::end(counter_columns));
    std::string text;
    const auto put_row = [&](const std::vector<std::string>& cells) {
        for (std::size_t i = 0; i < cells.size(); ++i) {
            if (i > 0) {
                text += ',';
            }
            text += csv_field(cells[i]);
        }
        text += "\n";
    };
    put_row(head);
    for (std::size_t i = 0; i < members.size(); ++i) {
        const SweepMember& m = members[i];
        std::vector<std::string> row = {fmt::format("{}", m.index), m.id, sweep.scenes[m.scene]};
        row.insert(row.end(), m.shown.begin(), m.shown.end());
        const std::optional<RunRecord>& r = records[i];
        if (!r) {
            row.insert(row.end(), {"not_run", "", ""});
        } else {
            row.insert(row.end(),
                       {r->ok ? "ok" : "failed", r->reason, fmt::format("{}", r->wall_s)});
        }
        for (const std::string& name : result_names) {
            row.push_back(r && r->results.contains(name) ? number_cell(r->results[name]) : "");
        }
        for (const char* c : counter_columns) {
            row.push_back(r && r->counters.contains(c) ? number_cell(r->counters[c]) : "");
        }
        put_row(row);
    }
    return text;
}

} // namespace ifsim::io
