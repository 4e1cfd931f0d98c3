#include "io/sweep/sweep_coordinator.hpp"

#include <algorithm>
#include <chrono>
#include <thread>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "io/cli/exit_codes.hpp"
#include "io/output/atomic_file.hpp"
#include "io/output/stop_signal.hpp"
#include "io/output/summary_writer.hpp"
#include "io/sweep/run_pool.hpp"

namespace ifsim::io {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Progress: one line per ended run with the count, failures and the time left.
class RunLines {
public:
    RunLines(const SweepOptions& opt, std::size_t total, int slots)
        : quiet_(opt.quiet), total_(total), slots_(std::max(1, slots)) {}

    void ended(const SweepPlan& plan, std::size_t member, const RunRecord& r, double wall, int rank,
               bool stopping) {
        ++done_;
        failed_ += r.ok ? 0 : 1;
        run_seconds_ += wall;
        if (quiet_) {
            return;
        }
        const std::size_t left = total_ - done_;
        const double eta = run_seconds_ / static_cast<double>(done_) * static_cast<double>(left) /
                           static_cast<double>(slots_);
        const SweepMember& m = plan.members[member];
        fmt::print(stderr, "ifsim sweep: [{}/{}] {:6} {:7.2f} s  {}runs/{}  {}{}{}\n", done_,
                   total_, r.ok ? "ok" : "FAILED", wall,
                   rank >= 0 ? fmt::format("rank {}  ", rank) : "", m.id, overrides_text(plan, m),
                   failed_ > 0 ? fmt::format("  ({} failed)", failed_) : "",
                   left > 0 && !stopping
                       ? fmt::format("  ~{:.0f} s left ({:.0f} s so far)", eta, seconds_since(t0_))
                       : "");
        if (!r.ok) {
            fmt::print(stderr, "ifsim sweep:   {}\n", r.reason);
        }
    }

private:
    bool quiet_;
    std::size_t total_;
    int slots_;
    std::size_t done_ = 0, failed_ = 0;
    double run_seconds_ = 0.0;
    Clock::time_point t0_ = Clock::now();
};

// A run that failed while the sweep was stopping was (most likely) stopped by it: not run, so
// the table does not show it as a failure and the next command runs it again.
void record_ended(SweepPlan& plan, std::size_t member, const RunRecord& r, int stopped) {
    if (stopped == 0 || r.ok) {
        set_record(plan, member, r);
    }
}

} // namespace

int run_members(SweepPlan& plan, const std::vector<std::size_t>& pending, const SweepLayout& layout,
                const SweepOptions& opt, RemoteWorkers* remote) {
    RunPool pool(layout.local_jobs);
    RunLines lines(opt, pending.size(),
                   layout.local_jobs + (remote != nullptr ? remote->slots() : 0));
    const int show_rank = remote != nullptr ? 0 : -1;
    std::size_t next = 0;
    int stopped = 0;
    const auto more = [&] { return stopped == 0 && next < pending.size(); };
    while (more() || !pool.empty() || (remote != nullptr && remote->outstanding() > 0)) {
        if (stopped == 0 && (stopped = stop_signal()) != 0) {
            pool.stop_all(); // each run writes its summary (interrupted) and ends
        }
        bool busy = false;
        while (more() && pool.has_free_slot()) {
            const std::size_t i = pending[next++];
            pool.start(i, prepare_run(plan, i, layout.threads, opt),
                       plan.run_dir(plan.members[i]) / "run.log");
            busy = true;
        }
        while (remote != nullptr && more() && remote->has_free_slot()) {
            const std::size_t i = pending[next++];
            remote->start(i, prepare_run(plan, i, layout.threads, opt),
                          plan.run_dir(plan.members[i]));
            busy = true;
        }
        if (const auto end = pool.poll()) {
            const RunRecord r =
                ended_run_record(plan, end->member, summary_text(plan, end->member), end->end);
            record_ended(plan, end->member, r, stopped);
            lines.ended(plan, end->member, r, end->wall_s, show_rank, stopped != 0);
            busy = true;
        }
        if (remote != nullptr) {
            if (const auto end = remote->poll()) {
                if (end->end.signal < 0) {
                    continue; // the worker was stopping and did not start it: not run
                }
                const RunRecord r =
                    ended_run_record(plan, end->member, end->summary_text, end->end);
                record_ended(plan, end->member, r, stopped);
                lines.ended(plan, end->member, r, end->wall_s, end->rank, stopped != 0);
                busy = true;
            }
        }
        if (!busy) {
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
    }
    return stopped != 0 ? stopped : stop_signal(); // a signal during the last run's end
}

namespace {

nlohmann::ordered_json sweep_json(const SweepPlan& plan, const SweepOptions& opt,
                                  const SweepLayout& layout, int slots, std::size_t reused,
                                  double wall, int stopped) {
    std::size_t ok = 0, failed = 0, not_run = 0;
    nlohmann::ordered_json runs = nlohmann::ordered_json::array();
    for (std::size_t i = 0; i < plan.members.size(); ++i) {
        const auto& r = plan.records[i];
        ok += r && r->ok;
        failed += r && !r->ok;
        not_run += !r;
        runs.push_back({{"run", plan.members[i].index},
                        {"id", plan.members[i].id},
                        {"status", !r      ? "not_run"
                                   : r->ok ? "ok"
                                           : "failed"},
                        {"overrides", plan.members[i].sets}});
    }
    nlohmann::ordered_json j;
    j["sweep"] = opt.sweep_file;
    j["status"] = stopped != 0 ? "interrupted" : failed > 0 ? "failed" : "ok";
    if (stopped != 0) {
        j["interrupted"] = signal_name(stopped);
    }
    j["runs"] = plan.members.size();
    j["ok"] = ok;
    j["failed"] = failed;
    j["not_run"] = not_run;
    j["reused"] = reused;
    j["ranks"] = layout.ranks;
    j["jobs"] = slots;
    j["threads_per_run"] = layout.threads;
    j["path"] = opt.scalar ? "scalar" : "simd";
    j["wall_s"] = wall;
    j["revision"] = build_revision();
    j["version"] = build_version();
    j["keys"] = swept_keys(plan.file);
    j["fixed"] = plan.file.fixed;
    j["table"] = stopped != 0 ? "sweep.csv.partial" : "sweep.csv";
    j["members"] = std::move(runs);
    return j;
}

} // namespace

SweepLayout local_layout(std::size_t pending, const SweepOptions& opt) {
    const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    SweepLayout s;
    s.local_jobs = opt.jobs > 0 ? opt.jobs : cores;
    s.local_jobs = std::clamp(s.local_jobs, 1, static_cast<int>(std::max<std::size_t>(1, pending)));
    s.threads = opt.threads_per_run > 0 ? opt.threads_per_run : std::max(1, cores / s.local_jobs);
    return s;
}

int coordinate_sweep(const SweepOptions& opt, SweepPlan& plan,
                     const std::vector<std::size_t>& pending, std::size_t reused,
                     const SweepLayout& layout, RemoteWorkers* remote) {
    const auto t0 = Clock::now();
    const int slots = layout.local_jobs + (remote != nullptr ? remote->slots() : 0);
    try {
        fs::create_directories(plan.out / "runs");
        std::error_code ignored;
        fs::remove(plan.out / "sweep.csv", ignored); // never left to pass for this sweep's
    } catch (const std::exception& e) {
        fmt::print(stderr, "ifsim sweep: error: cannot write {}: {}\n", plan.out.string(),
                   e.what());
        if (remote != nullptr) {
            remote->finish();
        }
        return exit_code::io_error;
    }
    if (!opt.quiet) {
        fmt::print(stderr,
                   "ifsim sweep: {} runs ({} finished earlier), {} at a time{} with {} "
                   "thread(s) each, into {}\n",
                   plan.members.size(), reused, slots,
                   layout.ranks > 1 ? fmt::format(" on {} ranks", layout.ranks) : "",
                   layout.threads, (plan.out / "runs").string());
    }
    int stopped = 0;
    try {
        const StopSignals signals;
        stopped = run_members(plan, pending, layout, opt, remote);
    } catch (const std::exception& e) {
        fmt::print(stderr, "ifsim sweep: error: {}\n", e.what());
        return exit_code::io_error;
    }
    const double wall = seconds_since(t0);
    const std::string csv = sweep_csv(plan.file, plan.members, plan.records);
    const nlohmann::ordered_json summary =
        sweep_json(plan, opt, layout, slots, reused, wall, stopped);
    try {
        write_file_atomically(plan.out / (stopped != 0 ? "sweep.csv.partial" : "sweep.csv"), csv);
        if (stopped == 0) {
            std::error_code ignored;
            fs::remove(plan.out / "sweep.csv.partial", ignored);
        }
        write_file_atomically(plan.out / "sweep.json", summary.dump(2) + "\n");
    } catch (const std::exception& e) {
        fmt::print(stderr, "ifsim sweep: error: {}\n", e.what());
        return exit_code::io_error;
    }
    const std::size_t ok = summary["ok"].get<std::size_t>();
    const std::size_t failed = summary["failed"].get<std::size_t>();
    if (stopped != 0) {
        fmt::print(stderr,
                   "ifsim sweep: interrupted by {}: {} of {} runs done; the same command goes on "
                   "(finished runs are kept)\n",
                   signal_name(stopped), ok + failed, plan.members.size());
        return interrupted_exit_code(stopped);
    }
    if (!opt.quiet) {
        fmt::print("ifsim sweep: {} runs, {} ok, {} failed in {:.1f} s; table {}\n",
                   plan.members.size(), ok, failed, wall, (plan.out / "sweep.csv").string());
    }
    return failed > 0 ? exit_code::run_failed : exit_code::ok;
}

} // namespace ifsim::io
