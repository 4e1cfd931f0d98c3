#pragma once
// A sweep being run: its members, what is known of each, where the runs go, and how one run is
// started and read back. Shared by the local queue and the MPI ranks.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "io/sweep/child_process.hpp"
#include "io/sweep/sweep_command.hpp"
#include "io/sweep/sweep_file.hpp"
#include "io/sweep/sweep_members.hpp"
#include "io/sweep/sweep_table.hpp"

namespace ifsim::io {

struct SweepPlan {
    SweepFile file;
    std::vector<SweepMember> members;
    std::vector<std::optional<RunRecord>> records; // per member; nullopt = not run (yet)
    std::filesystem::path out;

    std::filesystem::path run_dir(const SweepMember& m) const { return out / "runs" / m.id; }
};

// Reads and expands the sweep file (throws SceneError or std::runtime_error).
SweepPlan plan_sweep(const SweepOptions& options);

// The members to run, one per id (the same scene with the same overrides twice is one run),
// and the number of members whose folder already holds an "ok" summary of a run on the same
// kernel path (their records are filled in).
std::vector<std::size_t> pending_members(SweepPlan& plan, bool scalar, std::size_t& reused);

// Whether an earlier run's record can stand for a run on this kernel path.
bool reusable(const std::optional<RunRecord>& earlier, bool scalar);

// Prepares the member's folder (created; an older attempt's summary removed) and returns the
// command line of its run.
std::vector<std::string> prepare_run(const SweepPlan& plan, std::size_t member, int threads,
                                     const SweepOptions& options);

// The text of the member's summary.json ("" when it has none).
std::string summary_text(const SweepPlan& plan, std::size_t member);

// The record of an ended run from its summary's text ("" when it left none) and how it ended.
RunRecord ended_run_record(const SweepPlan& plan, std::size_t member,
                           const std::string& summary_text, const ProcessEnd& end);

// Gives the record to every member with the same id as `member`.
void set_record(SweepPlan& plan, std::size_t member, const RunRecord& record);

// The swept values of a member as one line ("interface.roughness=0.9 ...").
std::string overrides_text(const SweepPlan& plan, const SweepMember& member);

} // namespace ifsim::io
