// The shipped refined and unstructured shear-box scenes run to the end of their path and
// their peak mean shear stress stays within 3 % of the one-element box's (the refined box is
// not homogeneous: its free corners carry less, docs/fem.md "Mesh study").
#include <algorithm>
#include <string>

#include <gtest/gtest.h>

#include "tests/io/boundary_value_test_support.hpp"
#include "tests/io/scene_test_support.hpp"

namespace ifsim::io {
namespace {

double peak_of(const char* scene, const std::string& name) {
    const auto dir = test::fresh_dir(name);
    const test::CliRun r = test::run_cli_captured({"run", scene, "--out", dir.string(), "-q"});
    EXPECT_EQ(r.code, 0) << scene << ": " << r.err;
    EXPECT_EQ(test::summary(dir)["status"], "ok") << scene;
    const auto h = test::read_history(dir);
    double peak = 0.0;
    for (std::size_t k = 0; k < h.rows.size(); ++k) {
        peak = std::max(peak, h.number(k, "t_t1"));
    }
    return peak;
}

TEST(RefinedScenes, RunToTheEndNearTheOneElementPeak) {
    const double one = peak_of("scenes/fe-simple-shear-cnl-2d.toml", "one-2d");
    for (const char* s : {"scenes/fe-simple-shear-cnl-2d-refined.toml",
                          "scenes/fe-simple-shear-cnl-2d-unstructured.toml"}) {
        EXPECT_NEAR(peak_of(s, "refined-2d"), one, 0.03 * one) << s;
    }
    const double one_3d = peak_of("scenes/fe-simple-shear-cnl-3d.toml", "one-3d");
    EXPECT_NEAR(peak_of("scenes/fe-simple-shear-cnl-3d-refined.toml", "refined-3d"), one_3d,
                0.05 * one_3d);
}

// A refined box over the whole path with coarse steps goes through every new solver path
// (line search, acceptance at the noise floor, re-gathers, relaxed corner targets): one and two
// threads give the same history.csv byte for byte.
TEST(RefinedScenes, OneAndTwoThreadsGiveTheSameHistory) {
    std::string text[2];
    for (int t = 1; t <= 2; ++t) {
        const auto dir = test::fresh_dir("threads-" + std::to_string(t));
        const test::CliRun r = test::run_cli_captured(
            {"run", "scenes/fe-simple-shear-cnl-2d.toml", "--out", dir.string(), "-q", "--threads",
             std::to_string(t), "--set", "body.1.elements=[10, 2]", "--set", "stage.2.steps=120",
             "--set", "interface.subincrement=\"adaptive\""});
        ASSERT_EQ(r.code, 0) << r.err;
        const auto s = test::summary(dir);
        EXPECT_GT(s["counters"]["gathers"].get<long>(), 0);
        EXPECT_GT(s["counters"]["contact_relaxed_point_updates"].get<double>(), 0.0);
        EXPECT_GT(s["counters"]["line_search_steps"].get<long>(), 0);
        text[t - 1] = test::read_text(dir / "history.csv");
    }
    EXPECT_EQ(text[0], text[1]);
}

} // namespace
} // namespace ifsim::io
