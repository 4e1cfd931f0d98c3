#include "io/output/summary_writer.hpp"

#include <fstream>
#include <stdexcept>

#include <fmt/format.h>

#ifndef IFSIM_REVISION
#define IFSIM_REVISION "unknown"
#endif
#ifndef IFSIM_VERSION
#define IFSIM_VERSION "unknown"
#endif

namespace ifsim::io {

const char* build_revision() {
    return IFSIM_REVISION;
}
const char* build_version() {
    return IFSIM_VERSION;
}

nlohmann::ordered_json summary_json(const RunSummary& s) {
    nlohmann::ordered_json j;
    j["scene"] = s.scene;
    j["kind"] = s.kind.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(s.kind);
    j["status"] = s.ok ? "ok" : "failed";
    if (!s.ok) {
        j["reason"] = s.reason;
    }
    j["quality"] = s.warnings.empty() ? "clean" : "degraded";
    nlohmann::ordered_json warnings = nlohmann::ordered_json::array();
    for (const RunWarning& w : s.warnings) {
        warnings.push_back({{"code", w.code}, {"count", w.count}, {"message", w.message}});
    }
    j["warnings"] = warnings;
    j["threads"] = s.threads;
    j["revision"] = build_revision();
    j["version"] = build_version();
    nlohmann::ordered_json phases = nlohmann::ordered_json::object();
    for (const auto& [name, seconds] : s.phases) {
        phases[name] = seconds;
    }
    j["timing"] = {{"wall_s", s.wall_s}, {"phases", phases}};
    j["counters"] = s.counters;
    for (const auto& [key, value] : s.details.items()) {
        if (!j.contains(key)) {
            j[key] = value;
        }
    }
    return j;
}

void write_summary(const std::filesystem::path& dir, const RunSummary& summary) {
    const auto tmp = dir / summary_temp_name;
    {
        std::ofstream out(tmp, std::ios::trunc);
        // Replace, not throw, on invalid UTF-8 (a message quoting a damaged input file).
        out << summary_json(summary).dump(2, ' ', false,
                                          nlohmann::ordered_json::error_handler_t::replace)
            << '\n';
        out.flush();
        if (!out) {
            throw std::runtime_error(fmt::format("cannot write {}", tmp.string()));
        }
    }
    std::error_code ec;
    std::filesystem::rename(tmp, dir / summary_file_name, ec);
    if (ec) {
        throw std::runtime_error(fmt::format("cannot rename {} to {}: {}", tmp.string(),
                                             summary_file_name, ec.message()));
    }
}

} // namespace ifsim::io
