#include "io/output/run_folder.hpp"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>

namespace ifsim::io {
namespace fs = std::filesystem;

bool is_run_output(const std::string& name) {
    static const char* const exact[] = {
        "summary.json", "summary.json.tmp",   "history.csv", "history.csv.partial",
        "scene.toml",   "scene.toml.partial", "mesh.pvd",    "fields",
        "overview.png", "cycles.png",         "checkpoint",  "checkpoint.partial",
        "replay.toml",  "replay.toml.partial"};
    if (std::find(std::begin(exact), std::end(exact), name) != std::end(exact)) {
        return true;
    }
    const auto ends = [&](std::string_view s) { return name.ends_with(s); };
    return (name.starts_with("contact-") && (ends(".pvd") || ends(".pvd.partial"))) ||
           ends(".pvd.partial");
}

std::string FolderPreparation::message(const fs::path& dir) const {
    if (moved.empty()) {
        return "";
    }
    if (removed) {
        return fmt::format("replaced the earlier run in {} (--replace removed {} file(s))",
                           dir.string(), moved.size());
    }
    return fmt::format("the earlier run in {} was moved to {}", dir.string(), moved_to.string());
}

namespace {

std::string utc_stamp() {
    const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
    std::tm tm{};
    gmtime_r(&now, &tm);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y%m%dT%H%M%SZ", &tm);
    return buf;
}

} // namespace

namespace {

// Whether `entry` is one of `keep` or a folder holding one.
bool holds(const fs::path& entry, const std::vector<fs::path>& keep) {
    std::error_code ec;
    const fs::path e = fs::weakly_canonical(entry, ec);
    for (const fs::path& k : keep) {
        const fs::path kk = fs::weakly_canonical(k, ec);
        if (kk == e) {
            return true;
        }
        auto [a, b] = std::mismatch(e.begin(), e.end(), kk.begin(), kk.end());
        if (a == e.end() && b != kk.end()) {
            return true; // keep lies inside entry
        }
    }
    return false;
}

// --replace on fields/: the files a run writes there, then the folder when empty.
void remove_field_files(const fs::path& folder) {
    std::error_code ec;
    for (const fs::directory_entry& e : fs::directory_iterator(folder, ec)) {
        const std::string name = e.path().filename().string();
        const bool ours = (name.starts_with("mesh-") || name.starts_with("contact-")) &&
                          (name.ends_with(".vtu") || name.ends_with(".vtu.partial"));
        if (ours) {
            fs::remove(e.path(), ec);
        }
    }
    if (fs::is_empty(folder, ec)) {
        fs::remove(folder, ec);
    }
}

} // namespace

FolderPreparation prepare_run_folder(const fs::path& dir, bool replace,
                                     const std::vector<fs::path>& keep) {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec || !fs::is_directory(dir)) {
        throw std::runtime_error(fmt::format("cannot create the output directory {}: {}",
                                             dir.string(),
                                             ec ? ec.message() : "a file of that name exists"));
    }
    FolderPreparation prep;
    for (const fs::directory_entry& e : fs::directory_iterator(dir)) {
        const std::string name = e.path().filename().string();
        if (is_run_output(name) && !holds(e.path(), keep)) {
            prep.moved.push_back(name);
        }
    }
    std::sort(prep.moved.begin(), prep.moved.end());
    if (prep.moved.empty()) {
        return prep;
    }
    if (replace) {
        for (const std::string& name : prep.moved) {
            if (name == "fields" && fs::is_directory(dir / name)) {
                remove_field_files(dir / name);
                continue;
            }
            fs::remove_all(dir / name, ec);
            if (ec) {
                throw std::runtime_error(
                    fmt::format("cannot remove {}: {}", (dir / name).string(), ec.message()));
            }
        }
        prep.removed = true;
        return prep;
    }
    const std::string stamp = utc_stamp();
    fs::path target = dir / ("previous-" + stamp);
    for (int k = 2; fs::exists(target); ++k) {
        target = dir / fmt::format("previous-{}-{}", stamp, k);
    }
    fs::create_directory(target, ec);
    for (const std::string& name : prep.moved) {
        if (!ec) {
            fs::rename(dir / name, target / name, ec);
        }
    }
    if (ec) {
        throw std::runtime_error(fmt::format("cannot move the earlier run in {} to {}: {}",
                                             dir.string(), target.string(), ec.message()));
    }
    prep.moved_to = target;
    return prep;
}

} // namespace ifsim::io
