#include "io/sweep/sweep_plan.hpp"

#include <fstream>
#include <set>
#include <sstream>

#include <fmt/format.h>

#include "io/output/stop_signal.hpp"
#include "io/output/summary_writer.hpp"

namespace ifsim::io {

namespace fs = std::filesystem;

SweepPlan plan_sweep(const SweepOptions& options) {
    SweepPlan plan;
    plan.file = read_sweep_file(options.sweep_file);
    plan.members = expand_sweep(plan.file);
    plan.records.resize(plan.members.size());
    plan.out = options.out;
    return plan;
}

bool reusable(const std::optional<RunRecord>& earlier, bool scalar) {
    return earlier && earlier->ok && earlier->path == (scalar ? "scalar" : "simd");
}

std::vector<std::size_t> pending_members(SweepPlan& plan, bool scalar, std::size_t& reused) {
    std::vector<std::size_t> pending;
    std::set<std::string> queued;
    reused = 0;
    for (std::size_t i = 0; i < plan.members.size(); ++i) {
        std::optional<RunRecord> earlier = read_run_record(plan.run_dir(plan.members[i]));
        if (reusable(earlier, scalar)) {
            plan.records[i] = std::move(earlier);
            ++reused;
        } else if (queued.insert(plan.members[i].id).second) {
            pending.push_back(i);
        }
    }
    return pending;
}

std::vector<std::string> prepare_run(const SweepPlan& plan, std::size_t member, int threads,
                                     const SweepOptions& opt) {
    const SweepMember& m = plan.members[member];
    const fs::path dir = plan.run_dir(m);
    fs::create_directories(dir);
    std::error_code ignored;
    fs::remove(dir / summary_file_name, ignored); // an older attempt's is never read as this one's
    std::vector<std::string> argv = {opt.executable.empty() ? own_executable().string()
                                                            : opt.executable,
                                     "run",
                                     plan.file.paths[m.scene].string(),
                                     "--out",
                                     dir.string(),
                                     "--replace",
                                     "--quiet",
                                     "--threads",
                                     fmt::format("{}", threads)};
    if (opt.scalar) {
        argv.emplace_back("--scalar");
    }
    for (const std::string& s : m.sets) {
        argv.emplace_back("--set");
        argv.push_back(s);
    }
    return argv;
}

std::string summary_text(const SweepPlan& plan, std::size_t member) {
    std::ifstream in(plan.run_dir(plan.members[member]) / summary_file_name, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return in ? text.str() : std::string();
}

RunRecord ended_run_record(const SweepPlan& plan, std::size_t member,
                           const std::string& summary_text, const ProcessEnd& end) {
    if (auto r = run_record_from_text(summary_text)) {
        return *r;
    }
    const std::string log = (fs::path("runs") / plan.members[member].id / "run.log").string();
    if (end.signal != 0) {
        return failed_record(fmt::format("ifsim run ended by {} without a summary (see {})",
                                         signal_name(end.signal), log));
    }
    return failed_record(fmt::format("ifsim run exited with code {} without a summary (see {})",
                                     end.exit_code, log));
}

void set_record(SweepPlan& plan, std::size_t member, const RunRecord& record) {
    for (std::size_t i = 0; i < plan.members.size(); ++i) {
        if (plan.members[i].id == plan.members[member].id) {
            plan.records[i] = record;
        }
    }
}

std::string overrides_text(const SweepPlan& plan, const SweepMember& m) {
    // Only the swept values: the fixed ones are the same in every run.
    std::string text = plan.file.scenes.size() > 1 ? plan.file.scenes[m.scene] : "";
    for (std::size_t i = plan.file.fixed.size(); i < m.sets.size(); ++i) {
        if (!text.empty()) {
            text += ' ';
        }
        text += m.sets[i];
    }
    return text;
}

} // namespace ifsim::io
