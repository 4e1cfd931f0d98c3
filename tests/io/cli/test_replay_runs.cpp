// A run whose material or contact point fails writes DIR/replay.toml, names it in summary.json
// and its reason, and `ifsim run replay.toml` fails the same way: element tests (the failed
// step from its start state), interface tests and contact pairs of boundary-value problems
// (the failed Algorithm 1 call, scene kind "interface-point").

#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "io/cli/exit_codes.hpp"
#include "tests/io/scene_test_support.hpp"

namespace ifsim::io {
namespace {

namespace fs = std::filesystem;

nlohmann::json summary(const fs::path& dir) {
    return nlohmann::json::parse(test::read_text(dir / "summary.json"));
}

// The part of a reason after the first `marker` (the cause, without the step numbering,
// which a replay restarts).
std::string cause_of(const std::string& reason, const std::string& marker) {
    const auto at = reason.find(marker);
    std::string cause = at == std::string::npos ? reason : reason.substr(at + marker.size());
    // A replay's own failure names its own replay: not part of the cause.
    const auto own = cause.find(" (replay: ");
    return own == std::string::npos ? cause : cause.substr(0, own);
}

// Runs the scene, expects a failed run with a replay, runs the replay; returns both summaries.
std::pair<nlohmann::json, nlohmann::json> run_and_replay(const std::vector<std::string>& run_args,
                                                         const std::string& name) {
    const fs::path out = test::fresh_dir("replay-" + name);
    std::vector<std::string> args = {"run"};
    args.insert(args.end(), run_args.begin(), run_args.end());
    args.insert(args.end(), {"--out", out.string(), "-q"});
    const auto r = test::run_cli_captured(args);
    EXPECT_EQ(r.code, exit_code::run_failed) << r.err;
    const auto first = summary(out);
    EXPECT_EQ(first["status"], "failed");
    const fs::path replay = out / "replay.toml";
    EXPECT_TRUE(fs::exists(replay));
    EXPECT_EQ(first.value("replay", ""), replay.string());
    EXPECT_NE(first["reason"].get<std::string>().find("replay: ifsim run " + replay.string()),
              std::string::npos);
    const fs::path again = test::fresh_dir("replayed-" + name);
    const auto rr = test::run_cli_captured({"run", replay.string(), "--out", again.string(), "-q"});
    EXPECT_EQ(rr.code, exit_code::run_failed) << rr.err;
    return {first, summary(again)};
}

TEST(Replay, InterfaceTestPointFailsAgainAlone) {
    // kappa = 0.05: the continuum's sigma_p lies outside the band's limit surface.
    const auto [run, replay] =
        run_and_replay({"scenes/hard-cases/interface-hypo.toml", "--set",
                        "interface.roughness=0.05", "--set", "stage.1.steps=10"},
                       "interface-test");
    EXPECT_EQ(replay["kind"], "interface-point");
    const std::string cause = cause_of(replay["reason"], "in Algorithm 1: ");
    EXPECT_NE(cause.find("residual"), std::string::npos) << cause;
    // The same cause with the same residual, to the printed digits.
    EXPECT_NE(run["reason"].get<std::string>().find(cause), std::string::npos)
        << run["reason"] << "\n"
        << cause;
}

TEST(Replay, ContactPairPointOfABoundaryValueRunFailsAgainAlone) {
    const auto [run, replay] =
        // Without Algorithm 1's second try: with it this run completes (session 16).
        run_and_replay({"scenes/fe-simple-shear-cnl-2d.toml", "--set", "interface.roughness=0.05",
                        "--set", "stage.2.steps=10", "--set", "interface.newton_fallback=false"},
                       "boundary-value");
    EXPECT_EQ(replay["kind"], "interface-point");
    EXPECT_EQ(replay["ndim"], 2);
    const std::string cause = cause_of(replay["reason"], "in Algorithm 1: ");
    EXPECT_NE(run["reason"].get<std::string>().find(cause), std::string::npos)
        << run["reason"] << "\n"
        << cause;
}

TEST(Replay, ElementTestStepFailsAgainFromItsStartState) {
    // 20 small drained steps converge in two Newton iterations; the first step of the second
    // stage (5 % axial strain) cannot.
    const std::string scene =
        "kind = \"element-test\"\n[material]\nmodel = \"hypoplasticity\"\nparameters = "
        "\"karlsruhe-sand\"\n[initial]\nstress = [-100.0, -100.0, -100.0, 0.0, 0.0, 0.0]\n"
        "void_ratio = 0.6\n[integration]\nmax_newton_iterations = 2\n"
        "[[stage]]\nsteps = 20\ndeps_11 = -0.004\ndsig_22 = 0.0\ndsig_33 = 0.0\ndeps_12 = 0.0\n"
        "deps_13 = 0.0\ndeps_23 = 0.0\n"
        "[[stage]]\nsteps = 4\ndeps_11 = -0.2\ndsig_22 = 0.0\ndsig_33 = 0.0\ndeps_12 = 0.0\n"
        "deps_13 = 0.0\ndeps_23 = 0.0\n";
    const auto [run, replay] = run_and_replay({test::write_scene(scene, "element")}, "element");
    EXPECT_EQ(replay["kind"], "element-test");
    EXPECT_NE(run["reason"].get<std::string>().find("step 21 (stage 2, step 1 of 4)"),
              std::string::npos)
        << run["reason"];
    const std::string cause = cause_of(replay["reason"], "): ");
    EXPECT_NE(cause.find("did not converge in 2 iterations"), std::string::npos) << cause;
    EXPECT_NE(run["reason"].get<std::string>().find(cause), std::string::npos);
}

// Runs that stop for other reasons write no replay: a completed run, a scene error.
TEST(Replay, NoReplayWithoutAFailedPoint) {
    const fs::path out = test::fresh_dir("replay-none");
    const auto r = test::run_cli_captured(
        {"run", "scenes/element-hypo-oedometer.toml", "--out", out.string(), "-q"});
    ASSERT_EQ(r.code, exit_code::ok) << r.err;
    EXPECT_FALSE(fs::exists(out / "replay.toml"));
    EXPECT_FALSE(summary(out).contains("replay"));
}

} // namespace
} // namespace ifsim::io
