// `ifsim sweep` end to end with the real ifsim executable: every member runs into its folder
// with its overrides (the same history as a direct `ifsim run`), sweep.csv holds one row per
// run in sweep order, one job or two give the same table, a failed member is a row and not the
// end, and running again redoes only the runs that did not finish.

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "io/cli/exit_codes.hpp"
#include "io/sweep/sweep_command.hpp"
#include "io/sweep/sweep_file.hpp"
#include "io/sweep/sweep_members.hpp"
#include "tests/io/scene_test_support.hpp"

#ifndef IFSIM_EXECUTABLE
#error "IFSIM_EXECUTABLE (the ifsim binary the sweep runs) is set by tests/CMakeLists.txt"
#endif

namespace ifsim::io {
namespace {

namespace fs = std::filesystem;

const std::string grid = R"(
[grid]
"initial.void_ratio" = [0.65, 0.75]
"stage.2.deps_11" = [-0.002, -0.004]
)";

fs::path write_sweep(const std::string& body) {
    const fs::path dir = test::fresh_dir("sweep-runs");
    std::ofstream(dir / "base.toml") << test::valid_scene();
    std::ofstream(dir / "sweep.toml") << "scene = \"base.toml\"\n" << body;
    return dir / "sweep.toml";
}

int sweep(const fs::path& file, const fs::path& out, int jobs, bool scalar = false) {
    SweepOptions opt;
    opt.scalar = scalar;
    opt.sweep_file = file.string();
    opt.out = out.string();
    opt.jobs = jobs;
    opt.threads_per_run = 1;
    opt.quiet = true;
    opt.executable = IFSIM_EXECUTABLE;
    return sweep_command(opt);
}

std::vector<std::vector<std::string>> csv(const fs::path& file) {
    std::vector<std::vector<std::string>> rows;
    std::istringstream in(test::read_text(file));
    for (std::string line; std::getline(in, line);) {
        std::vector<std::string> cells;
        std::istringstream l(line);
        for (std::string c; std::getline(l, c, ',');) {
            cells.push_back(c);
        }
        rows.push_back(cells);
    }
    return rows;
}

std::size_t column(const std::vector<std::string>& head, const std::string& name) {
    const auto it = std::find(head.begin(), head.end(), name);
    EXPECT_NE(it, head.end()) << name;
    return static_cast<std::size_t>(it - head.begin());
}

nlohmann::json json_of(const fs::path& file) {
    return nlohmann::json::parse(test::read_text(file));
}

TEST(SweepRuns, EveryMemberRunsWithItsOverridesIntoOneTableRow) {
    const fs::path file = write_sweep(grid);
    const fs::path out = test::fresh_dir("sweep-out");
    ASSERT_EQ(sweep(file, out, 2), exit_code::ok);
    const auto rows = csv(out / "sweep.csv");
    ASSERT_EQ(rows.size(), 5u);
    const auto& head = rows[0];
    const std::size_t e = column(head, "initial.void_ratio");
    const std::size_t d = column(head, "stage.2.deps_11");
    const std::size_t status = column(head, "status");
    const std::size_t q = column(head, "peak_q");
    const char* expected[4][2] = {
        {"0.65", "-0.002"}, {"0.65", "-0.004"}, {"0.75", "-0.002"}, {"0.75", "-0.004"}};
    const auto members = expand_sweep(read_sweep_file(file));
    for (std::size_t i = 0; i < 4; ++i) {
        EXPECT_EQ(rows[i + 1][0], std::to_string(i + 1));
        EXPECT_EQ(rows[i + 1][1], members[i].id);
        EXPECT_EQ(rows[i + 1][e], expected[i][0]);
        EXPECT_EQ(rows[i + 1][d], expected[i][1]);
        EXPECT_EQ(rows[i + 1][status], "ok");
        // The run's own summary says it ran with the member's overrides.
        const auto s = json_of(out / "runs" / members[i].id / "summary.json");
        EXPECT_EQ(s["overrides"].get<std::vector<std::string>>(), members[i].sets);
    }
    // A larger axial strain increment reaches a larger q: the values did reach the runs.
    EXPECT_GT(std::stod(rows[2][q]), std::stod(rows[1][q]));
    const auto summary = json_of(out / "sweep.json");
    EXPECT_EQ(summary["status"], "ok");
    EXPECT_EQ(summary["ok"], 4);
    EXPECT_EQ(summary["reused"], 0);

    // The same run by hand gives the same history, byte for byte.
    const fs::path direct = test::fresh_dir("sweep-direct");
    std::vector<std::string> args = {"run",       (file.parent_path() / "base.toml").string(),
                                     "--out",     direct.string(),
                                     "--threads", "1",
                                     "-q"};
    for (const std::string& s : members[3].sets) {
        args.insert(args.end(), {"--set", s});
    }
    ASSERT_EQ(test::run_cli_captured(args).code, exit_code::ok);
    EXPECT_EQ(test::read_text(direct / "history.csv"),
              test::read_text(out / "runs" / members[3].id / "history.csv"));

    // One job at a time: the same table but for the wall times.
    const fs::path serial = test::fresh_dir("sweep-serial");
    ASSERT_EQ(sweep(file, serial, 1), exit_code::ok);
    auto a = csv(out / "sweep.csv"), b = csv(serial / "sweep.csv");
    const std::size_t wall = column(head, "wall_s");
    for (auto* t : {&a, &b}) {
        for (auto& r : *t) {
            r[wall].clear();
        }
    }
    EXPECT_EQ(a, b);
}

TEST(SweepRuns, RunningAgainRedoesOnlyUnfinishedRuns) {
    const fs::path file = write_sweep(grid);
    const fs::path out = test::fresh_dir("sweep-again");
    ASSERT_EQ(sweep(file, out, 2), exit_code::ok);
    const auto members = expand_sweep(read_sweep_file(file));
    const auto summary_of = [&](std::size_t i) {
        return out / "runs" / members[i].id / "summary.json";
    };
    std::vector<std::string> before;
    for (std::size_t i = 0; i < 4; ++i) {
        before.push_back(test::read_text(summary_of(i)));
    }
    fs::remove(summary_of(1)); // a killed run leaves no summary
    auto failed = json_of(summary_of(2));
    failed["status"] = "failed";
    failed["reason"] = "interrupted by SIGTERM";
    std::ofstream(summary_of(2)) << failed.dump();

    ASSERT_EQ(sweep(file, out, 2), exit_code::ok);
    const auto again = json_of(out / "sweep.json");
    EXPECT_EQ(again["reused"], 2);
    EXPECT_EQ(again["ok"], 4);
    EXPECT_EQ(test::read_text(summary_of(0)), before[0]) << "a finished run was run again";
    EXPECT_EQ(test::read_text(summary_of(3)), before[3]) << "a finished run was run again";
    EXPECT_EQ(json_of(summary_of(1))["status"], "ok");
    EXPECT_EQ(json_of(summary_of(2))["status"], "ok");
    EXPECT_NE(test::read_text(summary_of(2)), before[2]) << "the failed run was not redone";
}

TEST(SweepRuns, RunsAreReusedOnlyOnTheKernelPathAskedFor) {
    const fs::path file = write_sweep("[grid]\n\"initial.void_ratio\" = [0.7, 0.72]\n");
    const fs::path out = test::fresh_dir("sweep-path");
    ASSERT_EQ(sweep(file, out, 2), exit_code::ok);
    ASSERT_EQ(sweep(file, out, 2, true), exit_code::ok);
    auto summary = json_of(out / "sweep.json");
    EXPECT_EQ(summary["reused"], 0) << "SIMD runs stood in for scalar ones";
    EXPECT_EQ(summary["path"], "scalar");
    const auto members = expand_sweep(read_sweep_file(file));
    for (const auto& m : members) {
        EXPECT_EQ(json_of(out / "runs" / m.id / "summary.json")["path"], "scalar");
    }
    ASSERT_EQ(sweep(file, out, 2, true), exit_code::ok);
    EXPECT_EQ(json_of(out / "sweep.json")["reused"], 2);
}

TEST(SweepRuns, AFailedMemberIsARowAndTheOthersRun) {
    const fs::path file = write_sweep("[grid]\n\"initial.void_ratio\" = [0.7, -1.0, 0.72]\n");
    const fs::path out = test::fresh_dir("sweep-failed");
    EXPECT_EQ(sweep(file, out, 2), exit_code::run_failed);
    const auto rows = csv(out / "sweep.csv");
    ASSERT_EQ(rows.size(), 4u);
    const std::size_t status = column(rows[0], "status");
    const std::size_t reason = column(rows[0], "reason");
    EXPECT_EQ(rows[1][status], "ok");
    EXPECT_EQ(rows[2][status], "failed");
    EXPECT_NE(rows[2][reason].find("initial.void_ratio"), std::string::npos) << rows[2][reason];
    EXPECT_EQ(rows[3][status], "ok");
    EXPECT_EQ(json_of(out / "sweep.json")["status"], "failed");
}

TEST(SweepRuns, TheSameRunTwiceRunsOnce) {
    // Two entries of one scene: the same ids, one run each, both rows filled.
    const fs::path dir = write_sweep("").parent_path();
    std::ofstream(dir / "sweep.toml")
        << "scene = [\"base.toml\", \"base.toml\"]\n[grid]\n\"initial.void_ratio\" = [0.7]\n";
    const fs::path out = test::fresh_dir("sweep-twice");
    ASSERT_EQ(sweep(dir / "sweep.toml", out, 2), exit_code::ok);
    const auto rows = csv(out / "sweep.csv");
    ASSERT_EQ(rows.size(), 3u);
    EXPECT_EQ(rows[1][1], rows[2][1]);
    EXPECT_EQ(rows[1], [&] {
        auto r = rows[2];
        r[0] = "1";
        return r;
    }());
    EXPECT_EQ(std::distance(fs::directory_iterator(out / "runs"), fs::directory_iterator{}), 1);
}

TEST(SweepRuns, ABadSweepFileRunsNothing) {
    const fs::path file = write_sweep("[grid]\n\"initial.void_ratio\" = []\n");
    const fs::path out = test::fresh_dir("sweep-bad") / "out";
    EXPECT_EQ(sweep(file, out, 2), exit_code::bad_input);
    EXPECT_FALSE(fs::exists(out));
}

} // namespace
} // namespace ifsim::io
