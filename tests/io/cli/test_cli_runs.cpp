// The ifsim command line run in-process (run_cli, as main() calls it): complete runs write the
// contract's history.csv and summary.json; bad scenes and failed runs give a clear message, a
// failed summary and a non-zero exit code; kernel-bench prints its JSON object.

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "io/cli/cli.hpp"
#include "io/cli/exit_codes.hpp"
#include "tests/io/scene_test_support.hpp"

namespace ifsim::io {
namespace {

namespace fs = std::filesystem;

using Captured = test::CliRun;

Captured run_captured(const std::vector<std::string>& args) {
    return test::run_cli_captured(args);
}

nlohmann::json summary(const fs::path& dir) {
    return nlohmann::json::parse(test::read_text(dir / "summary.json"));
}

std::vector<std::string> lines(const fs::path& file) {
    std::istringstream in(test::read_text(file));
    std::vector<std::string> out;
    for (std::string l; std::getline(in, l);) {
        out.push_back(l);
    }
    return out;
}

std::vector<double> fields(const std::string& line) {
    std::vector<double> v;
    std::istringstream in(line);
    for (std::string f; std::getline(in, f, ',');) {
        v.push_back(std::stod(f));
    }
    return v;
}

const std::string header =
    "step,stage,eps11,eps22,eps33,eps12,eps13,eps23,s11,s22,s33,s12,s13,s23,e,"
    "h11,h22,h33,h12,h13,h23";

TEST(CliRun, WritesHistoryAndSummary) {
    const std::string scene = test::write_scene(test::valid_scene());
    const fs::path out = test::fresh_dir("cli-ok") / "new" / "dir";
    const Captured r = run_captured({"run", scene, "--out", out.string(), "--threads", "1"});
    ASSERT_EQ(r.code, exit_code::ok) << r.err;
    const auto rows = lines(out / "history.csv");
    ASSERT_EQ(rows.size(), 1u + 1u + 20u + 10u); // header, step 0, two stages
    EXPECT_EQ(rows[0], header);
    EXPECT_TRUE(rows[1].starts_with("0,0,0,0,0,0,0,0,-100,-50,-50,0,0,0,0.7,")) << rows[1];
    EXPECT_TRUE(rows.back().starts_with("30,2,")) << rows.back();
    // Lateral stresses of the triaxial stage stay at their value at its start.
    const auto end_oedometer = fields(rows[21]);
    const auto end = fields(rows.back());
    EXPECT_NEAR(end[9], end_oedometer[9], 1e-6 * std::abs(end_oedometer[9]));
    EXPECT_LT(end[8], end_oedometer[8]); // more axial compression

    const auto j = summary(out);
    EXPECT_EQ(j["status"], "ok");
    EXPECT_EQ(j["kind"], "element-test");
    EXPECT_EQ(j["scene"], scene);
    EXPECT_EQ(j["threads"], 1);
    EXPECT_EQ(j["path"], "simd");
    EXPECT_EQ(j["counters"]["increments"], 30);
    EXPECT_GE(j["counters"]["constitutive_evaluations"].get<long>(), 30);
    EXPECT_GT(j["counters"]["newton_iterations"].get<long>(), 0); // stage 2 is mixed control
    EXPECT_GE(j["counters"]["subincrements"].get<long>(), 30);
    for (const char* p : {"parse", "constitutive", "driver", "output"}) {
        EXPECT_TRUE(j["timing"]["phases"].contains(p)) << p;
    }
    EXPECT_FALSE(fs::exists(out / "summary.json.tmp"));
    EXPECT_FALSE(fs::exists(out / "history.csv.partial"));
}

TEST(CliRun, AppliesOverridesFromTheCommandLine) {
    const std::string scene = test::write_scene(test::valid_scene());
    const fs::path out = test::fresh_dir("cli-set");
    const Captured r = run_captured({"run", scene, "--out", out.string(), "--set",
                                     "stage.1.steps=3", "--set", "stage.2.steps=2", "--quiet"});
    ASSERT_EQ(r.code, exit_code::ok) << r.err;
    EXPECT_EQ(lines(out / "history.csv").size(), 1u + 1u + 3u + 2u);
    EXPECT_EQ(summary(out)["overrides"].size(), 2u);
    EXPECT_TRUE(r.out.empty()); // --quiet
}

TEST(CliRun, ScalarAndSimdPathsAgreeToRoundOff) {
    const std::string scene = test::write_scene(test::valid_scene());
    const fs::path a = test::fresh_dir("cli-simd");
    const fs::path b = test::fresh_dir("cli-scalar");
    ASSERT_EQ(run_captured({"run", scene, "--out", a.string()}).code, exit_code::ok);
    ASSERT_EQ(run_captured({"run", scene, "--out", b.string(), "--scalar"}).code, exit_code::ok);
    EXPECT_EQ(summary(b)["path"], "scalar");
    const auto ra = fields(lines(a / "history.csv").back());
    const auto rb = fields(lines(b / "history.csv").back());
    ASSERT_EQ(ra.size(), rb.size());
    for (std::size_t i = 0; i < ra.size(); ++i) {
        EXPECT_NEAR(ra[i], rb[i], 1e-9 * std::max(1.0, std::abs(ra[i]))) << i;
    }
}

TEST(CliRun, BadSceneNamesFileAndKeyAndWritesAFailedSummary) {
    const fs::path out = test::fresh_dir("cli-bad");
    // A complete old result in DIR must not survive as if it belonged to this run (it is moved
    // aside: CliRun.EarlierRunIsMovedAsideOrReplacedNeverMixedIn).
    std::ofstream(out / "summary.json") << R"({"status": "ok"})";
    std::ofstream(out / "history.csv") << "old\n";
    std::string text = test::valid_scene();
    text.replace(text.find("void_ratio = 0.7"), 16, "void_ratio = -1");
    const std::string scene = test::write_scene(text);
    const Captured r = run_captured({"run", scene, "--out", out.string()});
    EXPECT_EQ(r.code, exit_code::bad_input);
    EXPECT_NE(r.err.find(scene), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("initial.void_ratio"), std::string::npos) << r.err;
    const auto j = summary(out);
    EXPECT_EQ(j["status"], "failed");
    EXPECT_NE(j["reason"].get<std::string>().find("initial.void_ratio"), std::string::npos);
    EXPECT_FALSE(fs::exists(out / "history.csv"));
}

// An earlier run in DIR is moved aside whole (never destroyed, never left to pass for the new
// run's), the user's own files stay; --replace removes it instead.
TEST(CliRun, EarlierRunIsMovedAsideOrReplacedNeverMixedIn) {
    const fs::path out = test::fresh_dir("cli-earlier");
    const std::string scene = test::write_scene(test::valid_scene());
    ASSERT_EQ(run_captured({"run", scene, "--out", out.string()}).code, exit_code::ok);
    const std::string first_history = test::read_text(out / "history.csv");
    std::ofstream(out / "overview.png") << "plot of the first run";
    std::ofstream(out / "notes.txt") << "the user's own file";
    fs::create_directories(out / "fields");
    // A typo: the new run fails at parse time, the first run's results survive, moved aside.
    std::string bad = test::valid_scene();
    bad.replace(bad.find("void_ratio = 0.7"), 16, "void_ratio = -1");
    const Captured r = run_captured({"run", test::write_scene(bad), "--out", out.string()});
    EXPECT_EQ(r.code, exit_code::bad_input);
    EXPECT_NE(r.err.find("moved to"), std::string::npos) << r.err;
    std::vector<fs::path> previous;
    for (const auto& e : fs::directory_iterator(out)) {
        if (e.path().filename().string().starts_with("previous-")) {
            previous.push_back(e.path());
        }
    }
    ASSERT_EQ(previous.size(), 1u);
    EXPECT_EQ(test::read_text(previous[0] / "history.csv"), first_history);
    EXPECT_TRUE(fs::exists(previous[0] / "overview.png"));
    EXPECT_TRUE(fs::exists(previous[0] / "fields"));
    EXPECT_TRUE(fs::exists(previous[0] / "scene.toml"));
    EXPECT_FALSE(fs::exists(out / "overview.png"));
    EXPECT_FALSE(fs::exists(out / "history.csv"));
    EXPECT_TRUE(fs::exists(out / "notes.txt"));
    EXPECT_EQ(summary(out)["status"], "failed");
    // --replace: the failed attempt's summary is removed, nothing moved.
    ASSERT_EQ(run_captured({"run", scene, "--out", out.string(), "--replace"}).code, exit_code::ok);
    int dirs = 0;
    for (const auto& e : fs::directory_iterator(out)) {
        dirs += e.path().filename().string().starts_with("previous-") ? 1 : 0;
    }
    EXPECT_EQ(dirs, 1);
    EXPECT_EQ(test::read_text(out / "history.csv"), first_history);
}

// DIR/scene.toml is the scene as run, overrides applied: running it again gives the same
// history byte for byte.
TEST(CliRun, SceneCopyReproducesTheRun) {
    const fs::path out = test::fresh_dir("cli-copy");
    const std::string scene = test::write_scene(test::valid_scene());
    ASSERT_EQ(run_captured(
                  {"run", scene, "--out", (out / "a").string(), "--set", "initial.void_ratio=0.75"})
                  .code,
              exit_code::ok);
    const std::string copy = test::read_text(out / "a" / "scene.toml");
    EXPECT_NE(copy.find("--set initial.void_ratio=0.75"), std::string::npos) << copy;
    ASSERT_EQ(
        run_captured({"run", (out / "a" / "scene.toml").string(), "--out", (out / "b").string()})
            .code,
        exit_code::ok);
    EXPECT_EQ(test::read_text(out / "a" / "history.csv"),
              test::read_text(out / "b" / "history.csv"));
    EXPECT_EQ(summary(out / "a")["scene_copy"], "scene.toml");
    // Rerun in place, also with --replace: the scene being run is neither moved nor removed.
    for (const char* replace : {"--replace", "--quiet"}) {
        const Captured again = run_captured(
            {"run", (out / "a" / "scene.toml").string(), "--out", (out / "a").string(), replace});
        ASSERT_EQ(again.code, exit_code::ok) << again.err;
        EXPECT_EQ(test::read_text(out / "a" / "history.csv"),
                  test::read_text(out / "b" / "history.csv"));
    }
}

// --replace removes only what runs write: a user's file inside fields/ stays; a scene error
// never removes an earlier run, even with --replace.
TEST(CliRun, ReplaceRemovesOnlyRunOutputs) {
    const fs::path out = test::fresh_dir("cli-replace");
    const std::string scene = test::write_scene(test::valid_scene());
    ASSERT_EQ(run_captured({"run", scene, "--out", out.string()}).code, exit_code::ok);
    fs::create_directories(out / "fields");
    std::ofstream(out / "fields" / "mine.txt") << "keep me";
    std::ofstream(out / "fields" / "mesh-000001.vtu") << "an old field file";
    std::string bad = test::valid_scene();
    bad.replace(bad.find("void_ratio = 0.7"), 16, "void_ratio = -1");
    EXPECT_EQ(
        run_captured({"run", test::write_scene(bad), "--out", out.string(), "--replace"}).code,
        exit_code::bad_input);
    int previous = 0;
    for (const auto& e : fs::directory_iterator(out)) {
        previous += e.path().filename().string().starts_with("previous-") ? 1 : 0;
    }
    EXPECT_EQ(previous, 1); // moved aside, not removed
    fs::create_directories(out / "fields");
    std::ofstream(out / "fields" / "mine.txt") << "keep me";
    std::ofstream(out / "fields" / "mesh-000001.vtu") << "an old field file";
    ASSERT_EQ(run_captured({"run", scene, "--out", out.string(), "--replace"}).code, exit_code::ok);
    EXPECT_TRUE(fs::exists(out / "fields" / "mine.txt"));
    EXPECT_FALSE(fs::exists(out / "fields" / "mesh-000001.vtu"));
}

TEST(CliRun, BadOverrideIsReportedWithTheAssignment) {
    const std::string scene = test::write_scene(test::valid_scene());
    const fs::path out = test::fresh_dir("cli-bad-set");
    const Captured r =
        run_captured({"run", scene, "--out", out.string(), "--set", "material.rougness=0.5"});
    EXPECT_EQ(r.code, exit_code::bad_input);
    EXPECT_NE(r.err.find("material.rougness: unknown key"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("(from --set material.rougness=0.5)"), std::string::npos) << r.err;
}

TEST(CliRun, UnsupportedKindIsAClearError) {
    const std::string scene = test::write_scene("kind = \"fluid-flow\"\n");
    const fs::path out = test::fresh_dir("cli-kind");
    const Captured r = run_captured({"run", scene, "--out", out.string()});
    EXPECT_EQ(r.code, exit_code::bad_input);
    EXPECT_NE(r.err.find("kind: kind \"fluid-flow\" is not supported by this build"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(summary(out)["kind"], "fluid-flow");
    EXPECT_EQ(summary(out)["status"], "failed");
}

TEST(CliRun, UnreachableStressTargetFailsTheRunAndKeepsTheRows) {
    // Isotropic unloading by 150 kPa from 100 kPa: tension that a sand cannot carry.
    const std::string scene = test::write_scene(R"(kind = "element-test"
[material]
model = "hypoplasticity"
parameters = "karlsruhe-sand"
[initial]
stress = [-100.0, -100.0, -100.0, 0.0, 0.0, 0.0]
void_ratio = 0.7
[[stage]]
steps = 10
dsig_11 = 150.0
dsig_22 = 150.0
dsig_33 = 150.0
deps_12 = 0.0
deps_13 = 0.0
deps_23 = 0.0
)");
    const fs::path out = test::fresh_dir("cli-fail");
    const Captured r = run_captured({"run", scene, "--out", out.string()});
    EXPECT_EQ(r.code, exit_code::run_failed);
    EXPECT_NE(r.err.find("run failed"), std::string::npos) << r.err;
    const auto j = summary(out);
    EXPECT_EQ(j["status"], "failed");
    EXPECT_NE(j["reason"].get<std::string>().find("stage 1"), std::string::npos);
    const auto rows = lines(out / "history.csv");
    EXPECT_EQ(rows[0], header);
    EXPECT_GE(rows.size(), 2u);       // at least step 0
    EXPECT_LT(rows.size(), 1u + 11u); // not all steps
    EXPECT_EQ(j["rows"].get<std::size_t>(), rows.size() - 1);
}

TEST(CliRun, UsageErrorsAndHelp) {
    EXPECT_EQ(run_captured({"run"}).code, exit_code::bad_input);
    EXPECT_EQ(run_captured({"frobnicate"}).code, exit_code::bad_input);
    const Captured help = run_captured({"run", "--help"});
    EXPECT_EQ(help.code, exit_code::ok);
    EXPECT_NE(help.out.find("--set"), std::string::npos);
    EXPECT_NE(help.out.find("Exit codes"), std::string::npos);
    EXPECT_EQ(run_captured({"--help"}).code, exit_code::ok);
    const Captured missing = run_captured(
        {"run", "/nonexistent.toml", "--out", test::fresh_dir("cli-missing").string()});
    EXPECT_EQ(missing.code, exit_code::bad_input);
    EXPECT_NE(missing.err.find("/nonexistent.toml"), std::string::npos);
}

TEST(CliKernelBench, PrintsOneJsonObjectWithValidStates) {
    for (const char* model : {"hypoplasticity", "sanisand", "linear-elastic"}) {
        for (const bool scalar : {false, true}) {
            std::vector<std::string> args = {"kernel-bench", "--model",   model,
                                             "--points",     "50",        "--seconds",
                                             "0.02",         "--threads", "1"};
            if (scalar) {
                args.push_back("--scalar");
            }
            const Captured r = run_captured(args);
            ASSERT_EQ(r.code, exit_code::ok) << r.err;
            const auto j = nlohmann::json::parse(r.out);
            EXPECT_EQ(j["model"], model);
            EXPECT_TRUE(j["formulation"].is_null());
            EXPECT_EQ(j["points"], 50);
            EXPECT_EQ(j["threads"], 1);
            EXPECT_EQ(j["path"], scalar ? "scalar" : "simd");
            EXPECT_GT(j["evaluations_per_second"].get<double>(), 0.0);
            EXPECT_GT(j["points_per_second"].get<double>(), 0.0);
            EXPECT_GE(j["updates"].get<long>(), 1);
            EXPECT_GE(j["substeps_per_evaluation"].get<double>(), 1.0);
            EXPECT_EQ(j["failed_points"], 0) << model;
        }
    }
}

TEST(CliKernelBench, RejectsUnknownFormulationsAndBadOptions) {
    const Captured f = run_captured(
        {"kernel-bench", "--model", "hypoplasticity", "--formulation", "mohr", "--points", "8"});
    EXPECT_EQ(f.code, exit_code::bad_input);
    EXPECT_NE(f.err.find("expected none, novel, stutz or coulomb"), std::string::npos) << f.err;
    EXPECT_EQ(run_captured({"kernel-bench", "--model", "cam-clay", "--points", "8"}).code,
              exit_code::bad_input);
    EXPECT_EQ(run_captured({"kernel-bench", "--model", "sanisand", "--points", "0"}).code,
              exit_code::bad_input);
    EXPECT_EQ(run_captured({"kernel-bench", "--model", "sanisand"}).code, exit_code::bad_input);
}

} // namespace
} // namespace ifsim::io
