// The scalar results summary.json gives (and sweep.csv gathers), read from history.csv: the
// right columns, the peak of the shear magnitude, q of a general stress, torn rows skipped.

#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "io/output/history_results.hpp"
#include "tests/io/scene_test_support.hpp"

namespace ifsim::io {
namespace {

namespace fs = std::filesystem;

fs::path write_history(const std::string& text) {
    const fs::path p = test::fresh_dir("results") / "history.csv";
    std::ofstream(p) << text;
    return p;
}

TEST(HistoryResults, InterfaceColumnsGivePeakAndFinalValues) {
    const fs::path p = write_history("step,u_t1,u_n,t_n,t_t1,t_t2,e_interface\n"
                                     "0,0,0,-100,0,0,0.8\n"
                                     "1,0.001,-1e-5,-100,30,40,0.79\n" // |t_t| = 50
                                     "2,0.002,2e-5,-101,45,0,0.81\n"
                                     "3,0.003,3e-5,-99,-44,"); // torn: ignored
    const auto r = history_results(p);
    EXPECT_EQ(r["rows"], 3);
    EXPECT_DOUBLE_EQ(r["peak_shear_stress"].get<double>(), 50.0);
    EXPECT_DOUBLE_EQ(r["final_shear_stress"].get<double>(), 45.0);
    EXPECT_DOUBLE_EQ(r["final_normal_stress"].get<double>(), -101.0);
    EXPECT_DOUBLE_EQ(r["final_shear_displacement"].get<double>(), 0.002);
    EXPECT_DOUBLE_EQ(r["final_normal_displacement"].get<double>(), 2e-5);
    EXPECT_DOUBLE_EQ(r["final_interface_void_ratio"].get<double>(), 0.81);
    EXPECT_FALSE(r.contains("peak_q"));
}

TEST(HistoryResults, StressColumnsGiveMeanStressAndQ) {
    // Triaxial compression: q = |s11 - s22|; with a shear stress q = sqrt(3) |s12| on top.
    const fs::path p = write_history("step,s11,s22,s33,s12,s13,s23,e\n"
                                     "0,-100,-100,-100,0,0,0,0.7\n"
                                     "1,-400,-100,-100,0,0,0,0.68\n"
                                     "2,-100,-100,-100,10,0,0,\n"); // e empty: skipped
    const auto r = history_results(p);
    EXPECT_DOUBLE_EQ(r["peak_q"].get<double>(), 300.0);
    EXPECT_NEAR(r["final_q"].get<double>(), std::sqrt(3.0) * 10.0, 1e-12);
    EXPECT_DOUBLE_EQ(r["final_mean_stress"].get<double>(), -100.0);
    EXPECT_DOUBLE_EQ(r["final_void_ratio"].get<double>(), 0.68);
    EXPECT_FALSE(r.contains("peak_shear_stress"));
}

TEST(HistoryResults, NoFileOrNoRowsGiveNothing) {
    EXPECT_TRUE(history_results(test::fresh_dir("none") / "history.csv").empty());
    EXPECT_TRUE(history_results(write_history("step,t_t1\n")).empty());
}

} // namespace
} // namespace ifsim::io
