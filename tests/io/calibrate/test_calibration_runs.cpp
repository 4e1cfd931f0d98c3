// `ifsim calibrate` end to end with the real ifsim executable: a curve made by ifsim itself at
// known roughness and band thickness is fitted from elsewhere, and the known values come back —
// to the solver's tolerance from clean data, within the noise's reach from noisy data. A second
// calibration reuses the runs of the first.

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "io/calibrate/calibrate_command.hpp"
#include "io/cli/exit_codes.hpp"
#include "tests/io/scene_test_support.hpp"

#ifndef IFSIM_EXECUTABLE
#error "IFSIM_EXECUTABLE (the ifsim binary the calibration runs) is set by tests/CMakeLists.txt"
#endif

namespace ifsim::io {
namespace {

namespace fs = std::filesystem;

constexpr double kappa_true = 0.85;
constexpr double band_true = 0.0025;

const std::string scene = fs::absolute("scenes/simple-shear-cnl-stutz.toml").string();
const std::vector<std::string> fixed = {"interface.subincrement=\"adaptive\"", "stage.1.steps=200"};

// The "measured" curve: every 5th row of an ifsim run, with Gaussian noise of relative size
// noise_t on t_t and absolute noise_n on u_n.
fs::path measured_curve(const fs::path& dir, double noise_t, double noise_n) {
    const fs::path truth = dir / "truth";
    std::vector<std::string> args = {"run", scene, "--out", truth.string(), "-q", "--threads", "1"};
    for (const std::string& s : fixed) {
        args.insert(args.end(), {"--set", s});
    }
    args.insert(args.end(), {"--set", "interface.roughness=0.85", "--set",
                             "interface.shear_band_thickness=0.0025"});
    EXPECT_EQ(test::run_cli_captured(args).code, exit_code::ok);
    std::istringstream in(test::read_text(truth / "history.csv"));
    std::string line;
    std::getline(in, line); // u_t1 is column 2, u_n 4, t_t1 6
    std::mt19937 random(7);
    std::normal_distribution<double> normal(0.0, 1.0);
    std::ofstream out(dir / "measured.csv");
    out << "u_t,t_t,u_n\n";
    for (int row = 0; std::getline(in, line); ++row) {
        std::vector<double> f;
        std::istringstream l(line);
        for (std::string c; std::getline(l, c, ',');) {
            f.push_back(std::stod(c));
        }
        if (row % 5 == 0) {
            out << f[2] << "," << f[6] * (1.0 + noise_t * normal(random)) << ","
                << f[4] + noise_n * normal(random) << "\n";
        }
    }
    return dir / "measured.csv";
}

nlohmann::json calibrate(const fs::path& dir, const fs::path& data, const fs::path& out) {
    std::ofstream(dir / "cal.toml") << "scene = \"" << scene << "\"\ndata = \"" << data.string()
                                    << "\"\n[parameters]\n"
                                       "\"interface.roughness\" = { initial = 0.7, bounds = "
                                       "[0.5, 0.95] }\n"
                                       "\"interface.shear_band_thickness\" = { initial = 0.0015, "
                                       "bounds = [0.001, 0.006] }\n[set]\n"
                                       "\"interface.subincrement\" = \"adaptive\"\n"
                                       "\"stage.1.steps\" = 200\n";
    CalibrateOptions opt;
    opt.file = (dir / "cal.toml").string();
    opt.runs.out = out.string();
    opt.runs.jobs = 2;
    opt.runs.threads_per_run = 1;
    opt.runs.quiet = true;
    opt.runs.executable = IFSIM_EXECUTABLE;
    EXPECT_EQ(calibrate_command(opt), exit_code::ok);
    return nlohmann::json::parse(test::read_text(out / "calibration.json"));
}

double fitted(const nlohmann::json& j, std::size_t k) {
    return j["parameters"][k]["fitted"].get<double>();
}

TEST(CalibrationRuns, CleanDataGiveBackTheValuesTheyWereMadeWith) {
    const fs::path dir = test::fresh_dir("cal-clean");
    const fs::path data = measured_curve(dir, 0.0, 0.0);
    const auto j = calibrate(dir, data, dir / "out");
    EXPECT_TRUE(j["converged"].get<bool>()) << j["termination"];
    EXPECT_NEAR(fitted(j, 0), kappa_true, 1e-3);
    EXPECT_NEAR(fitted(j, 1) / band_true, 1.0, 0.01);
    EXPECT_LT(j["rms_t_t"].get<double>(), 0.05); // kPa
    EXPECT_LT(j["final_cost"].get<double>(), 1e-4 * j["initial_cost"].get<double>());
    // The same calibration again finds every run done.
    const auto again = calibrate(dir, data, dir / "out");
    EXPECT_EQ(again["reused_runs"], again["evaluations"]);
    EXPECT_EQ(fitted(again, 0), fitted(j, 0));
}

TEST(CalibrationRuns, NoisyDataGiveBackTheValuesWithinTheNoise) {
    const fs::path dir = test::fresh_dir("cal-noisy");
    const auto j = calibrate(dir, measured_curve(dir, 0.01, 1e-6), dir / "out");
    EXPECT_NEAR(fitted(j, 0), kappa_true, 0.01);
    EXPECT_NEAR(fitted(j, 1) / band_true, 1.0, 0.1);
    // The fit's shear residual is about the noise (1 % of ~60 kPa).
    EXPECT_LT(j["rms_t_t"].get<double>(), 1.0);
    EXPECT_TRUE(fs::exists(dir / "out" / "fit.csv"));
    EXPECT_TRUE(fs::exists(dir / "out" / "evaluations.csv"));
}

} // namespace
} // namespace ifsim::io
