// Sweep files read and expanded: grid order (last key fastest), zip, fixed overrides, value
// text that --set reads back as the same TOML value, run ids by content, and the errors that
// name the key.

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "io/scene/scene_error.hpp"
#include "io/sweep/sweep_file.hpp"
#include "io/sweep/sweep_members.hpp"
#include "io/sweep/sweep_table.hpp"
#include "tests/io/scene_test_support.hpp"

namespace ifsim::io {
namespace {

namespace fs = std::filesystem;

// A sweep file next to a copy of the small valid scene.
fs::path write_sweep(const std::string& body) {
    const fs::path dir = test::fresh_dir("sweep");
    std::ofstream(dir / "base.toml") << test::valid_scene();
    std::ofstream(dir / "sweep.toml") << body;
    return dir / "sweep.toml";
}

std::string error_of(const fs::path& file) {
    try {
        read_sweep_file(file);
    } catch (const SceneError& e) {
        return std::string(e.key()) + " | " + e.what();
    }
    return "";
}

TEST(SweepFile, GridExpandsInFileOrderWithTheLastKeyFastest) {
    const fs::path f = write_sweep(R"(scene = "base.toml"
[grid]
"initial.void_ratio" = [0.6, 0.7, 0.8]
"material.parameters" = ["karlsruhe-sand", "l4c"]
[set]
"stage.1.steps" = 5
)");
    const SweepFile sweep = read_sweep_file(f);
    ASSERT_EQ(sweep.runs(), 6u);
    const auto members = expand_sweep(sweep);
    ASSERT_EQ(members.size(), 6u);
    EXPECT_EQ(swept_keys(sweep),
              (std::vector<std::string>{"initial.void_ratio", "material.parameters"}));
    EXPECT_EQ(members[0].sets,
              (std::vector<std::string>{"stage.1.steps=5", "initial.void_ratio=0.6",
                                        "material.parameters=\"karlsruhe-sand\""}));
    EXPECT_EQ(members[1].shown, (std::vector<std::string>{"0.6", "l4c"}));
    EXPECT_EQ(members[5].shown, (std::vector<std::string>{"0.8", "l4c"}));
    std::set<std::string> ids;
    for (std::size_t i = 0; i < members.size(); ++i) {
        EXPECT_EQ(members[i].index, i + 1);
        ids.insert(members[i].id);
    }
    EXPECT_EQ(ids.size(), 6u) << "every run has its own folder";
}

TEST(SweepFile, ZipPairsValuesAndCombinesWithTheGrid) {
    const fs::path f = write_sweep(R"(scene = ["base.toml", "base.toml"]
[zip]
"initial.void_ratio" = [0.6, 0.7]
"stage.1.steps" = [4, 8]
[grid]
"material.parameters" = ["karlsruhe-sand", "l4c"]
)");
    const auto members = expand_sweep(read_sweep_file(f));
    ASSERT_EQ(members.size(), 2u * 2u * 2u);
    EXPECT_EQ(members[0].shown, (std::vector<std::string>{"karlsruhe-sand", "0.6", "4"}));
    EXPECT_EQ(members[1].shown, (std::vector<std::string>{"karlsruhe-sand", "0.7", "8"}));
    EXPECT_EQ(members[2].shown, (std::vector<std::string>{"l4c", "0.6", "4"}));
    EXPECT_EQ(members[4].scene, 1u);
    // The same scene text with the same overrides is the same run.
    EXPECT_EQ(members[0].id, members[4].id);
}

TEST(SweepFile, ValuesKeepTheirTomlType) {
    const fs::path f = write_sweep(R"(scene = "base.toml"
[grid]
"a.b" = [1.0, 1, 0.8, 1e-5, -2.5e10, "x \"y\"", true, [1.0, 2]]
)");
    const SweepAxis a = read_sweep_file(f).grid.at(0);
    EXPECT_EQ(a.values, (std::vector<std::string>{"1.0", "1", "0.8", "1e-05", "-25000000000.0",
                                                  "\"x \\\"y\\\"\"", "true", "[1.0, 2]"}));
    EXPECT_EQ(a.display[5], "x \"y\"");
    // Each text reads back as the value it came from.
    for (std::size_t i = 0; i < a.values.size(); ++i) {
        const toml::table t = toml::parse("v = " + a.values[i]);
        EXPECT_EQ(toml_value_text(*t.get("v")), a.values[i]);
    }
}

TEST(SweepFile, RunIdsFollowContentNotOrder) {
    const std::string text = test::valid_scene();
    EXPECT_EQ(run_id(text, {"a=1", "b=2"}), run_id(text, {"b=2", "a=1"}));
    EXPECT_NE(run_id(text, {"a=1", "b=2"}), run_id(text, {"a=1", "b=3"}));
    EXPECT_NE(run_id(text, {"a=1"}), run_id(text + " ", {"a=1"}));
    EXPECT_NE(run_id(text, {"a=1", "b=2"}), run_id(text, {"a=1b=2"}));
    EXPECT_EQ(run_id(text, {}).size(), 16u);
}

TEST(SweepFile, MistakesNameTheKey) {
    EXPECT_NE(error_of(write_sweep("[grid]\n\"a.b\" = [1]\n")).find("scene |"), std::string::npos);
    EXPECT_NE(error_of(write_sweep("scene = \"missing.toml\"\n")).find("missing.toml"),
              std::string::npos);
    EXPECT_NE(error_of(write_sweep("scene = \"base.toml\"\n[grid]\n\"a.b\" = []\n"))
                  .find("grid.\"a.b\" |"),
              std::string::npos);
    EXPECT_NE(error_of(write_sweep("scene = \"base.toml\"\n[grid]\n\"a.b\" = 3\n"))
                  .find("non-empty list"),
              std::string::npos);
    EXPECT_NE(error_of(write_sweep("scene = \"base.toml\"\n[zip]\n\"a\" = [1, 2]\n\"b\" = [1]\n"))
                  .find("zip.\"b\" |"),
              std::string::npos);
    EXPECT_NE(error_of(write_sweep("scene = \"base.toml\"\n[grid]\n\"a\" = [1]\n[zip]\n\"a\" = "
                                   "[1]\n"))
                  .find("swept once"),
              std::string::npos);
    EXPECT_NE(error_of(write_sweep("scene = \"base.toml\"\ngird = 1\n")).find("gird"),
              std::string::npos);
    EXPECT_NE(error_of(write_sweep("scene = \"base.toml\"\n[grid]\n\"a\" = [1]\n[set]\n\"a\" = "
                                   "2\n"))
                  .find("set.\"a\""),
              std::string::npos);
}

TEST(SweepTable, CsvQuotesFieldsThatNeedIt) {
    EXPECT_EQ(csv_field("plain"), "plain");
    EXPECT_EQ(csv_field("a,b"), "\"a,b\"");
    EXPECT_EQ(csv_field("say \"no\""), "\"say \"\"no\"\"\"");
}

} // namespace
} // namespace ifsim::io
