// Field output of boundary-value runs ([output] fields, --fields): written exactly when the
// schedule says (every N increments, stage ends, the first increment at or after a named
// time, and the initial state), listed in the collections with the history's times, absent
// when not asked for; bad keys stop the run before anything is computed. The files' content is
// read back by meshio and VTK in the FieldFiles.* tests (scripts/check_fields.py).
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "io/element_test/element_checkpoint.hpp"
#include "tests/io/boundary_value_test_support.hpp"
#include "tests/io/scene_test_support.hpp"

namespace ifsim::io {
namespace {

namespace fs = std::filesystem;

const char* const box = "scenes/fe-simple-shear-cnl-2d.toml";

test::CliRun run(const fs::path& dir, std::vector<std::string> extra) {
    std::vector<std::string> args = {"run",   box,
                                     "--out", dir.string(),
                                     "--set", "stage.2.steps=20",
                                     "--set", "stage.2.displacement.1.change=0.0002"};
    args.insert(args.end(), extra.begin(), extra.end());
    return test::run_cli_captured(args);
}

// The increments of the files listed in a collection, with their times.
std::vector<std::pair<long, double>> listed(const fs::path& pvd) {
    std::ifstream in(pvd);
    std::stringstream s;
    s << in.rdbuf();
    const std::string text = s.str();
    std::vector<std::pair<long, double>> out;
    const std::regex entry("timestep=\"([^\"]+)\"[^>]*file=\"fields/[a-z-]+-(\\d+)\\.vtu\"");
    for (auto it = std::sregex_iterator(text.begin(), text.end(), entry);
         it != std::sregex_iterator(); ++it) {
        out.emplace_back(std::stol((*it)[2]), std::stod((*it)[1]));
    }
    return out;
}

TEST(Fields, NoneWithoutBeingAskedFor) {
    const fs::path dir = test::fresh_dir("fields-none");
    ASSERT_EQ(run(dir, {}).code, 0);
    EXPECT_FALSE(fs::exists(dir / "fields"));
    EXPECT_FALSE(fs::exists(dir / "mesh.pvd"));
    EXPECT_FALSE(test::summary(dir).contains("fields"));
}

// Consolidation is increment 1 (stage 1's end), the shear increments 2..21 (stage 2).
TEST(Fields, WrittenExactlyWhenTheScheduleSays) {
    const fs::path dir = test::fresh_dir("fields-schedule");
    const auto r = run(dir, {"--set", "output.fields={ every = 8, stages = false, times = [1.52, "
                                      "1.0] }"});
    ASSERT_EQ(r.code, 0) << r.err;
    const auto h = test::read_history(dir);
    // 0 always; 8 and 16 (every); time 1.0 -> increment 1; 1.52 -> first time >= 1.52.
    std::set<long> expected = {0, 1, 8, 16};
    for (std::size_t k = 0; k < h.rows.size(); ++k) {
        if (h.number(k, "time") >= 1.52 - 1e-12) {
            expected.insert(static_cast<long>(h.number(k, "increment")));
            break;
        }
    }
    const auto mesh = listed(dir / "mesh.pvd");
    std::set<long> got;
    for (const auto& [increment, time] : mesh) {
        got.insert(increment);
        EXPECT_TRUE(fs::exists(dir / "fields" / fmt::format("mesh-{:06d}.vtu", increment)));
        EXPECT_DOUBLE_EQ(time, h.number(static_cast<std::size_t>(increment), "time"));
    }
    EXPECT_EQ(got, expected);
    // The contact pair is paired at the first increment: its series starts there.
    const auto contact = listed(dir / "contact-interface.pvd");
    ASSERT_EQ(contact.size(), mesh.size() - 1);
    EXPECT_EQ(contact.front().first, 1);
    EXPECT_EQ(test::summary(dir)["fields"]["outputs"].get<long>(),
              static_cast<long>(expected.size()));
}

TEST(Fields, SwitchWritesEveryStageEnd) {
    const fs::path dir = test::fresh_dir("fields-switch");
    ASSERT_EQ(run(dir, {"--fields"}).code, 0);
    const auto mesh = listed(dir / "mesh.pvd");
    ASSERT_EQ(mesh.size(), 3u); // initial state, end of stage 1, end of stage 2
    EXPECT_EQ(mesh[1].first, 1);
    EXPECT_EQ(mesh[2].first, 21);
}

TEST(Fields, BadScheduleNamesTheKey) {
    const fs::path dir = test::fresh_dir("fields-bad");
    auto r = run(dir, {"--set", "output.fields={ every = 2, when = 3 }"});
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("output.fields"), std::string::npos) << r.err;
    r = run(dir, {"--set", "output.fields={ times = [-1.0] }"});
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("output.fields.times"), std::string::npos) << r.err;
    r = run(dir, {"--set", "output.fields=\"yes\""});
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("output.fields"), std::string::npos) << r.err;
    const auto element = test::run_cli_captured(
        {"run", "scenes/element-hypo-oedometer.toml", "--out", dir.string(), "--fields"});
    EXPECT_EQ(element.code, 2);
    EXPECT_NE(element.err.find("boundary-value"), std::string::npos) << element.err;
}

} // namespace
} // namespace ifsim::io

namespace ifsim::io {
namespace {

// summary.json "effects" lists what the run built: the shear box has one novel hypoplastic
// pair, hypoplastic sand with intergranular strain, no gravity, no K0, no fields; the
// two-pair scene lists both pairs; --fields shows up as fields: true.
TEST(Effects, SummaryListsWhatTheRunBuilt) {
    const fs::path dir = test::fresh_dir("effects-box");
    ASSERT_EQ(run(dir, {}).code, 0);
    const auto e = test::summary(dir)["effects"];
    EXPECT_EQ(e["kinematics"], "small-strain");
    EXPECT_EQ(e["dimension"], 2);
    EXPECT_FALSE(e["gravity"].get<bool>());
    EXPECT_FALSE(e["fields"].get<bool>());
    EXPECT_FALSE(e["checkpoints"].get<bool>());
    ASSERT_EQ(e["contact_pairs"].size(), 1u);
    EXPECT_EQ(e["contact_pairs"][0]["formulation"], "novel");
    EXPECT_EQ(e["contact_pairs"][0]["model"], "hypoplasticity");
    ASSERT_EQ(e["materials"].size(), 2u);
    EXPECT_EQ(e["materials"][0]["model"], "hypoplasticity");
    EXPECT_TRUE(e["materials"][0]["intergranular_strain"].get<bool>());
    EXPECT_FALSE(e["materials"][0]["k0"].get<bool>());
    const fs::path two = test::fresh_dir("effects-two");
    const auto r = test::run_cli_captured({"run", "scenes/fe-rough-and-smooth-2d.toml", "--out",
                                           two.string(), "--fields", "--checkpoint-every", "50"});
    ASSERT_EQ(r.code, 0) << r.err;
    const auto e2 = test::summary(two)["effects"];
    EXPECT_EQ(e2["contact_pairs"].size(), 2u);
    EXPECT_TRUE(e2["fields"].get<bool>());
    EXPECT_TRUE(e2["checkpoints"].get<bool>());
    EXPECT_NE(r.err.find("fields: yes"), std::string::npos) << r.err;
}

} // namespace
} // namespace ifsim::io

namespace ifsim::io {
namespace {

// ifsim resume refuses what it cannot continue and changes nothing: no checkpoint (a finished
// run removed it), a damaged one; every kind writes checkpoints and removes them when complete.
// The killed-and-resumed runs themselves are checked byte for byte by scripts/check_resume.py
// (Checkpoint.* tests).
TEST(Resume, RefusesWhatItCannotContinueAndChangesNothing) {
    const fs::path dir = test::fresh_dir("resume-refused");
    const auto r = run(dir, {"--checkpoint-every", "5"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_FALSE(fs::exists(dir / "checkpoint")); // complete: nothing to resume
    EXPECT_EQ(test::summary(dir)["checkpoints"]["written"].get<long>(), 4);
    // By time (a tiny interval: after every increment that took longer): the same history.
    const fs::path timed = test::fresh_dir("resume-timed");
    ASSERT_EQ(run(timed, {"--checkpoint-minutes", "1e-7"}).code, 0);
    EXPECT_GT(test::summary(timed)["checkpoints"]["written"].get<long>(), 0);
    EXPECT_FALSE(fs::exists(timed / "checkpoint"));
    const std::string history = test::read_text(dir / "history.csv");
    EXPECT_EQ(test::read_text(timed / "history.csv"), history);
    auto again = test::run_cli_captured({"resume", dir.string()});
    EXPECT_EQ(again.code, 2);
    EXPECT_NE(again.err.find("cannot open the checkpoint"), std::string::npos) << again.err;
    std::ofstream(dir / "checkpoint") << "not a checkpoint";
    again = test::run_cli_captured({"resume", dir.string()});
    EXPECT_EQ(again.code, 2);
    EXPECT_NE(again.err.find("not an ifsim checkpoint"), std::string::npos) << again.err;
    EXPECT_EQ(test::read_text(dir / "history.csv"), history);
    // Every kind writes checkpoints and removes them once complete.
    const fs::path el = test::fresh_dir("resume-element");
    ASSERT_EQ(test::run_cli_captured({"run", "scenes/element-hypo-oedometer.toml", "--out",
                                      el.string(), "-q", "--checkpoint-every", "5"})
                  .code,
              0);
    EXPECT_FALSE(fs::exists(el / "checkpoint"));
    EXPECT_GT(test::summary(el)["checkpoints"]["written"].get<long>(), 0);
    // A checkpoint whose scene is not DIR/scene.toml: refused, nothing changes.
    const std::string el_history = test::read_text(el / "history.csv");
    ElementTestCheckpoint c;
    c.run.scene_text = "kind = \"element-test\"\n# another scene\n";
    c.position.state = {-100.0, -100.0, -100.0, 0.0, 0.0, 0.0, 0.7};
    write_element_test_checkpoint(el, c);
    again = test::run_cli_captured({"resume", el.string()});
    EXPECT_EQ(again.code, 2);
    EXPECT_NE(again.err.find("is not the scene the checkpoint was written for"), std::string::npos)
        << again.err;
    EXPECT_EQ(test::read_text(el / "history.csv"), el_history);
    // A well-formed checkpoint of this scene whose position is not in it (a stage past the
    // end): refused before history.csv is touched.
    c.run.scene_text = test::read_text(el / "scene.toml");
    c.position.stage = 7;
    write_element_test_checkpoint(el, c);
    again = test::run_cli_captured({"resume", el.string()});
    EXPECT_EQ(again.code, 2);
    EXPECT_NE(again.err.find("does not fit"), std::string::npos) << again.err;
    EXPECT_NE(again.err.find("stage 8"), std::string::npos) << again.err;
    EXPECT_EQ(test::read_text(el / "history.csv"), el_history);
}

} // namespace
} // namespace ifsim::io
