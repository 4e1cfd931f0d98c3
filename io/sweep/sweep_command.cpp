#include "io/sweep/sweep_command.hpp"

#include <signal.h>
#include <sys/types.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <map>
#include <optional>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "io/cli/exit_codes.hpp"
#include "io/output/atomic_file.hpp"
#include "io/output/stop_signal.hpp"
#include "io/output/summary_writer.hpp"
#include "io/scene/scene_error.hpp"
#include "io/sweep/child_process.hpp"
#include "io/sweep/sweep_file.hpp"
#include "io/sweep/sweep_members.hpp"
#include "io/sweep/sweep_table.hpp"

namespace ifsim::io {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

struct Sweep {
    SweepFile file;
    std::vector<SweepMember> members;
    std::vector<std::optional<RunRecord>> records; // per member; nullopt = not run
    fs::path out;
    fs::path run_dir(const SweepMember& m) const { return out / "runs" / m.id; }
};

// The command line of one run.
std::vector<std::string> run_command_line(const Sweep& sweep, const SweepMember& m, int threads,
                                          const SweepOptions& opt) {
    std::vector<std::string> argv = {opt.executable.empty() ? own_executable().string()
                                                            : opt.executable,
                                     "run",
                                     sweep.file.paths[m.scene].string(),
                                     "--out",
                                     sweep.run_dir(m).string(),
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

std::string overrides_text(const SweepMember& m, const SweepFile& file) {
    // Only the swept values: the fixed ones are the same in every run.
    std::string text;
    for (std::size_t i = file.fixed.size(); i < m.sets.size(); ++i) {
        if (!text.empty()) {
            text += ' ';
        }
        text += m.sets[i];
    }
    if (file.scenes.size() > 1) {
        text = text.empty() ? file.scenes[m.scene] : file.scenes[m.scene] + ' ' + text;
    }
    return text;
}

// The record of a child that ended: its summary, or how it ended without one.
RunRecord ended_run(const Sweep& sweep, const SweepMember& m, const ProcessEnd& end) {
    if (auto r = read_run_record(sweep.run_dir(m))) {
        return *r;
    }
    const std::string log = (fs::path("runs") / m.id / "run.log").string();
    if (end.signal != 0) {
        return failed_record(fmt::format("ifsim run ended by {} without a summary (see {})",
                                         signal_name(end.signal), log));
    }
    return failed_record(fmt::format("ifsim run exited with code {} without a summary (see {})",
                                     end.exit_code, log));
}

struct Schedule {
    int jobs = 1;
    int threads = 1;
};

Schedule schedule_for(std::size_t pending, const SweepOptions& opt) {
    const int cores = std::max(1u, std::thread::hardware_concurrency());
    Schedule s;
    s.jobs = opt.jobs > 0 ? opt.jobs : cores;
    s.jobs =
        std::max(1, std::min<int>(s.jobs, static_cast<int>(std::max<std::size_t>(1, pending))));
    s.threads = opt.threads_per_run > 0 ? opt.threads_per_run : std::max(1, cores / s.jobs);
    return s;
}

// Runs the pending members as a queue over `jobs` child processes. Returns the stop signal
// that ended it early, or 0.
int run_queue(Sweep& sweep, const std::vector<std::size_t>& pending, const Schedule& schedule,
              const SweepOptions& opt) {
    const auto t0 = Clock::now();
    std::map<pid_t, std::size_t> running; // child -> member position
    std::map<pid_t, Clock::time_point> started;
    std::size_t next = 0, done = 0, failed = 0;
    double run_seconds = 0.0;
    int stopped = 0;
    while (next < pending.size() || !running.empty()) {
        if (stopped == 0 && (stopped = stop_signal()) != 0) {
            for (const auto& [pid, i] : running) {
                ::kill(pid, SIGTERM); // each run writes its summary ("interrupted") and ends
            }
        }
        while (stopped == 0 && next < pending.size() &&
               static_cast<int>(running.size()) < schedule.jobs) {
            const std::size_t i = pending[next++];
            const SweepMember& m = sweep.members[i];
            const fs::path dir = sweep.run_dir(m);
            fs::create_directories(dir);
            std::error_code ignored;
            fs::remove(dir / summary_file_name, ignored); // never read an older attempt's
            const pid_t pid =
                start_process(run_command_line(sweep, m, schedule.threads, opt), dir / "run.log");
            running[pid] = i;
            started[pid] = Clock::now();
        }
        const std::optional<ProcessEnd> end = finished_child();
        if (!end) {
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
            continue;
        }
        const auto it = running.find(end->pid);
        if (it == running.end()) {
            continue; // not one of ours
        }
        const std::size_t i = it->second;
        const SweepMember& m = sweep.members[i];
        const double wall = seconds_since(started[end->pid]);
        running.erase(it);
        started.erase(end->pid);
        sweep.records[i] = ended_run(sweep, m, *end);
        ++done;
        run_seconds += wall;
        failed += sweep.records[i]->ok ? 0 : 1;
        if (!opt.quiet) {
            const std::size_t left = pending.size() - done;
            const double eta = run_seconds / static_cast<double>(done) * static_cast<double>(left) /
                               static_cast<double>(schedule.jobs);
            fmt::print(stderr, "ifsim sweep: [{}/{}] {:6} {:7.2f} s  runs/{}  {}{}{}\n", done,
                       pending.size(), sweep.records[i]->ok ? "ok" : "FAILED", wall, m.id,
                       overrides_text(m, sweep.file),
                       failed > 0 ? fmt::format("  ({} failed)", failed) : "",
                       left > 0 && stopped == 0 ? fmt::format("  ~{:.0f} s left ({:.0f} s so far)",
                                                              eta, seconds_since(t0))
                                                : "");
            if (!sweep.records[i]->ok) {
                fmt::print(stderr, "ifsim sweep:   {}\n", sweep.records[i]->reason);
            }
        }
    }
    return stopped;
}

nlohmann::ordered_json sweep_json(const Sweep& sweep, const SweepOptions& opt,
                                  const Schedule& schedule, std::size_t reused, double wall,
                                  int stopped) {
    std::size_t ok = 0, failed = 0, not_run = 0;
    nlohmann::ordered_json runs = nlohmann::ordered_json::array();
    for (std::size_t i = 0; i < sweep.members.size(); ++i) {
        const auto& r = sweep.records[i];
        const char* status = !r ? "not_run" : r->ok ? "ok" : "failed";
        ok += r && r->ok;
        failed += r && !r->ok;
        not_run += !r;
        runs.push_back({{"run", sweep.members[i].index},
                        {"id", sweep.members[i].id},
                        {"status", status},
                        {"overrides", sweep.members[i].sets}});
    }
    nlohmann::ordered_json j;
    j["sweep"] = opt.sweep_file;
    j["status"] = stopped != 0 ? "interrupted" : failed > 0 ? "failed" : "ok";
    if (stopped != 0) {
        j["interrupted"] = signal_name(stopped);
    }
    j["runs"] = sweep.members.size();
    j["ok"] = ok;
    j["failed"] = failed;
    j["not_run"] = not_run;
    j["reused"] = reused;
    j["jobs"] = schedule.jobs;
    j["threads_per_run"] = schedule.threads;
    j["path"] = opt.scalar ? "scalar" : "simd";
    j["wall_s"] = wall;
    j["revision"] = build_revision();
    j["version"] = build_version();
    j["keys"] = swept_keys(sweep.file);
    j["fixed"] = sweep.file.fixed;
    j["table"] = stopped != 0 ? "sweep.csv.partial" : "sweep.csv";
    j["members"] = std::move(runs);
    return j;
}

} // namespace

int sweep_command(const SweepOptions& opt) {
    const auto t0 = Clock::now();
    Sweep sweep;
    try {
        sweep.file = read_sweep_file(opt.sweep_file);
        sweep.members = expand_sweep(sweep.file);
    } catch (const SceneError& e) {
        fmt::print(stderr, "ifsim sweep: error: {}\n", e.what());
        return exit_code::bad_input;
    } catch (const std::exception& e) {
        fmt::print(stderr, "ifsim sweep: error: {}\n", e.what());
        return exit_code::bad_input;
    }
    if (opt.list) {
        for (const SweepMember& m : sweep.members) {
            fmt::print("{} {} {}", m.index, m.id, sweep.file.scenes[m.scene]);
            for (const std::string& s : m.sets) {
                fmt::print(" --set {}", s);
            }
            fmt::print("\n");
        }
        return exit_code::ok;
    }
    sweep.out = opt.out;
    sweep.records.resize(sweep.members.size());
    std::vector<std::size_t> pending;
    std::size_t reused = 0;
    for (std::size_t i = 0; i < sweep.members.size(); ++i) {
        std::optional<RunRecord> earlier = read_run_record(sweep.run_dir(sweep.members[i]));
        if (earlier && earlier->ok) {
            sweep.records[i] = std::move(earlier);
            ++reused;
        } else {
            pending.push_back(i);
        }
    }
    const Schedule schedule = schedule_for(pending.size(), opt);
    try {
        fs::create_directories(sweep.out / "runs");
        std::error_code ignored;
        fs::remove(sweep.out / "sweep.csv", ignored); // never left to pass for this sweep's
    } catch (const std::exception& e) {
        fmt::print(stderr, "ifsim sweep: error: cannot write {}: {}\n", sweep.out.string(),
                   e.what());
        return exit_code::io_error;
    }
    if (!opt.quiet) {
        fmt::print(stderr,
                   "ifsim sweep: {} runs ({} finished earlier), {} at a time with {} thread(s) "
                   "each, into {}\n",
                   sweep.members.size(), reused, schedule.jobs, schedule.threads,
                   (sweep.out / "runs").string());
    }
    int stopped = 0;
    try {
        const StopSignals signals;
        stopped = run_queue(sweep, pending, schedule, opt);
    } catch (const std::exception& e) {
        fmt::print(stderr, "ifsim sweep: error: {}\n", e.what());
        return exit_code::io_error;
    }
    const double wall = seconds_since(t0);
    const std::string csv = sweep_csv(sweep.file, sweep.members, sweep.records);
    const nlohmann::ordered_json summary = sweep_json(sweep, opt, schedule, reused, wall, stopped);
    try {
        write_file_atomically(sweep.out / (stopped != 0 ? "sweep.csv.partial" : "sweep.csv"), csv);
        if (stopped == 0) {
            std::error_code ignored;
            fs::remove(sweep.out / "sweep.csv.partial", ignored);
        }
        write_file_atomically(sweep.out / "sweep.json", summary.dump(2) + "\n");
    } catch (const std::exception& e) {
        fmt::print(stderr, "ifsim sweep: error: {}\n", e.what());
        return exit_code::io_error;
    }
    const std::size_t failed = summary["failed"].get<std::size_t>();
    if (stopped != 0) {
        fmt::print(stderr,
                   "ifsim sweep: interrupted by {}: {} of {} runs done; the same command goes on "
                   "(finished runs are kept)\n",
                   signal_name(stopped), summary["ok"].get<std::size_t>() + failed,
                   sweep.members.size());
        return interrupted_exit_code(stopped);
    }
    if (!opt.quiet) {
        fmt::print("ifsim sweep: {} runs, {} ok, {} failed in {:.1f} s; table {}\n",
                   sweep.members.size(), summary["ok"].get<std::size_t>(), failed, wall,
                   (sweep.out / "sweep.csv").string());
    }
    return failed > 0 ? exit_code::run_failed : exit_code::ok;
}

} // namespace ifsim::io
