// Measured curves against runs: path-length parametrisation (cyclic data compare by path, not
// by u_t), interpolation, scaled residuals, runs that stop short, and data files with
// mistakes named by column and row.

#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "io/calibrate/calibration_file.hpp"
#include "io/calibrate/measured_curve.hpp"
#include "io/scene/scene_error.hpp"
#include "tests/io/scene_test_support.hpp"

namespace ifsim::io {
namespace {

namespace fs = std::filesystem;

fs::path write(const fs::path& dir, const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return dir / name;
}

CurvePoints curve(std::vector<double> u_t, std::vector<double> t_t, std::vector<double> u_n) {
    CurvePoints c;
    double s = 0.0, last = 0.0;
    for (const double u : u_t) {
        s += std::abs(u - last);
        last = u;
        c.path.push_back(s);
    }
    c.u_t = std::move(u_t);
    c.t_t = std::move(t_t);
    c.u_n = std::move(u_n);
    return c;
}

TEST(MeasuredCurve, CyclicDataAreComparedByPathLength) {
    const fs::path dir = test::fresh_dir("curve");
    // Forth to 2 mm and back to 0: the second visit of u_t = 1 mm is at path 3 mm.
    const CurvePoints data = read_measured_curve(
        write(dir, "d.csv", "u_t,t_t,u_n,other\n0.001,10,0,x\n0.002,20,1e-5,y\n0.001,-5,2e-5,z\n"),
        "u_t", "t_t", "u_n");
    EXPECT_EQ(data.path, (std::vector<double>{0.001, 0.002, 0.003}));
    // A run sampled more finely along the same path.
    const CurvePoints run = curve({0.0, 0.0015, 0.002, 0.0015, 0.0}, {0, 15, 20, 2.5, -10},
                                  {0, 0.5e-5, 1e-5, 1.5e-5, 2.5e-5});
    const CurvePoints at = run_at_data_points(data, run);
    EXPECT_DOUBLE_EQ(at.t_t[0], 10.0); // 2/3 of the way to 15
    EXPECT_DOUBLE_EQ(at.t_t[1], 20.0);
    // Path 3 mm lies a third of the way from path 2.5 mm (t = 2.5) to 4 mm (t = -10), on the
    // way back; by u_t alone it would be read on the way out.
    EXPECT_NEAR(at.t_t[2], 2.5 - 12.5 / 3.0, 1e-12);
    const CurveScales scales = curve_scales(data);
    EXPECT_DOUBLE_EQ(scales.t_t, 20.0);
    EXPECT_DOUBLE_EQ(scales.u_n, 2e-5);
    const auto r = curve_residuals(data, run, scales, 2.0);
    ASSERT_TRUE(r);
    ASSERT_EQ(r->size(), 6u);
    EXPECT_NEAR((*r)[2], (2.5 - 12.5 / 3.0 + 5.0) / 20.0, 1e-12);
    EXPECT_NEAR((*r)[5], 2.0 * (1.5e-5 + 1e-5 / 3.0 - 2e-5) / 2e-5, 1e-9);
    // Without u_n weight: the shear residuals only.
    EXPECT_EQ(curve_residuals(data, run, scales, 0.0)->size(), 3u);
}

TEST(MeasuredCurve, ARunThatStopsShortHasNoResiduals) {
    const CurvePoints data = curve({0.001, 0.002}, {1, 2}, {});
    const CurvePoints run = curve({0.0, 0.0015}, {0, 1.5}, {0, 0});
    EXPECT_FALSE(curve_residuals(data, run, curve_scales(data), 1.0));
}

TEST(MeasuredCurve, MistakesNameTheColumnAndRow) {
    const fs::path dir = test::fresh_dir("curve-bad");
    const auto error = [&](const std::string& text) {
        try {
            read_measured_curve(write(dir, "d.csv", text), "u_t", "t_t", "u_n");
        } catch (const SceneError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_NE(error("u,t_t\n0,1\n1,2\n").find("column named u_t"), std::string::npos);
    EXPECT_NE(error("u_t,t_t\n0,1\n0.001,abc\n").find("data row 2"), std::string::npos);
    EXPECT_NE(error("u_t,t_t\n0,1\n").find("at least 2"), std::string::npos);
    EXPECT_TRUE(error("u_t,t_t\n0,1\n0.001,2\n").empty()) << "u_n is optional";
}

TEST(CalibrationFile, ReadsParametersInFileOrderAndChecksBounds) {
    const fs::path dir = test::fresh_dir("cal-file");
    write(dir, "base.toml", test::valid_scene());
    write(dir, "d.csv", "u_t,t_t\n0,0\n0.001,1\n");
    const CalibrationFile cal = read_calibration_file(write(dir, "c.toml", R"(scene = "base.toml"
data = "d.csv"
[parameters]
"z.last" = { initial = 2.0, bounds = [1.0, 3.0] }
"a.first" = { initial = 0.5, bounds = [0.0, 1.0] }
[set]
"stage.1.steps" = 4
[fit]
weight_u_n = 0.5
)"));
    ASSERT_EQ(cal.parameters.size(), 2u);
    EXPECT_EQ(cal.parameters[0].key, "z.last");
    EXPECT_EQ(cal.fixed, (std::vector<std::string>{"stage.1.steps=4"}));
    EXPECT_DOUBLE_EQ(cal.weight_u_n, 0.5);
    const auto error = [&](const std::string& body) {
        try {
            read_calibration_file(write(dir, "bad.toml", body));
        } catch (const SceneError& e) {
            return std::string(e.key());
        }
        return std::string();
    };
    const std::string head = "scene = \"base.toml\"\ndata = \"d.csv\"\n";
    EXPECT_EQ(error(head + "[parameters]\n\"a\" = { initial = 2.0, bounds = [0.0, 1.0] }\n"),
              "parameters.\"a\".bounds");
    EXPECT_EQ(error(head + "[parameters]\n\"a\" = 0.5\n"), "parameters.\"a\"");
    EXPECT_EQ(error(head), "parameters");
    EXPECT_EQ(error("scene = \"base.toml\"\ndata = \"none.csv\"\n"), "data");
    EXPECT_EQ(error(head + "[parameters]\n\"a\" = { initial = 0.5, bounds = [0.0, 1.0] }\n"
                           "[set]\n\"a\" = 1\n"),
              "set.\"a\"");
}

} // namespace
} // namespace ifsim::io
