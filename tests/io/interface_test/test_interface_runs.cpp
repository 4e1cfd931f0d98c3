// `ifsim run` on interface-test scenes, in-process (run_cli, as main() calls it): history.csv
// has the contract's columns, step 0 holds the initial interface stress of each formulation,
// CNL keeps t_n, CNS keeps t_n = t_n0 - K u_n on the sample, Coulomb friction stays inside its
// cone, and summary.json carries the interface counters and phases. Short runs with adaptive
// sub-increments keep the suite fast.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
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

Captured run_captured(std::vector<std::string> args) {
    return test::run_cli_captured(std::move(args));
}

// history.csv as its header and rows of named numbers.
struct History {
    std::string header;
    std::vector<std::map<std::string, double>> rows;
};

History read_history(const fs::path& dir) {
    std::istringstream in(test::read_text(dir / "history.csv"));
    History h;
    std::getline(in, h.header);
    std::vector<std::string> names;
    std::istringstream hs(h.header);
    for (std::string n; std::getline(hs, n, ',');) {
        names.push_back(n);
    }
    for (std::string line; std::getline(in, line);) {
        std::istringstream ls(line);
        std::map<std::string, double> row;
        std::size_t k = 0;
        for (std::string f; std::getline(ls, f, ','); ++k) {
            row[names.at(k)] = std::stod(f);
        }
        EXPECT_EQ(k, names.size()) << line;
        h.rows.push_back(row);
    }
    return h;
}

nlohmann::json summary(const fs::path& dir) {
    return nlohmann::json::parse(test::read_text(dir / "summary.json"));
}

// A short CNL simple interface shear test: L4C, t_N = 100 kPa, K0 = 0.5, 0.3 mm in 10 steps.
std::string scene(const std::string& interface_lines, const std::string& normal = "",
                  const std::string& stress = "[-100.0, -50.0, -60.0, 0.0, 0.0, 0.0]") {
    return "kind = \"interface-test\"\n[interface]\n" + interface_lines +
           "\n[sample]\nvoid_ratio = 0.81\nstress = " + stress + "\n" + normal +
           "\n[[stage]]\nsteps = 10\ndu_t1 = 0.0003\n";
}

const std::string adaptive_novel = "formulation = \"novel\"\nsubincrement = \"adaptive\"";

const std::string contract_columns =
    "step,stage,u_t1,u_t2,u_n,t_n,t_t1,t_t2,s_n,s_p1,s_p2,eps_n,eps_p1,eps_p2,gamma1,gamma2,"
    "band_thickness,sample_s11,sample_s22,sample_s33,e_interface,e_sample";

TEST(InterfaceRun, HistoryHasTheContractColumnsAndOneRowPerStep) {
    const std::string file = test::write_scene(scene(adaptive_novel));
    const fs::path out = test::fresh_dir("iface-header");
    const Captured r = run_captured({"run", file, "--out", out.string(), "--threads", "1"});
    ASSERT_EQ(r.code, exit_code::ok) << r.err;
    const History h = read_history(out);
    EXPECT_EQ(h.header, contract_columns + ",sample_s12,sample_s13,slip1,slip2,newton_iterations");
    ASSERT_EQ(h.rows.size(), 11u);
    for (std::size_t i = 0; i < h.rows.size(); ++i) {
        EXPECT_EQ(h.rows[i].at("step"), static_cast<double>(i));
        EXPECT_EQ(h.rows[i].at("stage"), i == 0 ? 0.0 : 1.0);
        EXPECT_NEAR(h.rows[i].at("u_t1"), 3.0e-5 * static_cast<double>(i), 1e-15);
    }
    EXPECT_NE(r.out.find("ok: 10 steps"), std::string::npos) << r.out;
    EXPECT_FALSE(fs::exists(out / "history.csv.partial"));
    EXPECT_FALSE(fs::exists(out / "summary.json.tmp"));
}

TEST(InterfaceRun, StepZeroHoldsTheInitialInterfaceStressOfEachInitialisation) {
    struct Case {
        std::string lines;
        double s_n, s_p1, s_p2;
    };
    const Case cases[] = {
        {adaptive_novel, -100.0, -50.0, -60.0},
        {"formulation = \"stutz\"\nsubincrement = \"adaptive\"\nstutz_initial_stress = "
         "\"continuum\"",
         -100.0, -50.0, -60.0},
        {"formulation = \"stutz\"\nsubincrement = \"adaptive\"\nstutz_initial_stress = "
         "\"normal-contact\"",
         -100.0, -100.0, -100.0},
    };
    for (const Case& c : cases) {
        const std::string file = test::write_scene(scene(c.lines));
        const fs::path out = test::fresh_dir("iface-init");
        const Captured r =
            run_captured({"run", file, "--out", out.string(), "--set", "stage.1.steps=1"});
        ASSERT_EQ(r.code, exit_code::ok) << c.lines << r.err;
        const History h = read_history(out);
        ASSERT_FALSE(h.rows.empty());
        const auto& row0 = h.rows[0];
        EXPECT_EQ(row0.at("s_n"), c.s_n) << c.lines;
        EXPECT_EQ(row0.at("s_p1"), c.s_p1) << c.lines;
        EXPECT_EQ(row0.at("s_p2"), c.s_p2) << c.lines;
        EXPECT_EQ(row0.at("t_n"), -100.0);
        EXPECT_EQ(row0.at("sample_s22"), -50.0);
        EXPECT_EQ(row0.at("sample_s33"), -60.0);
        EXPECT_EQ(row0.at("e_interface"), 0.81);
        EXPECT_EQ(row0.at("band_thickness"), 0.003);
        for (const char* zero : {"u_t1", "u_n", "t_t1", "eps_n", "eps_p1", "gamma1", "slip1"}) {
            EXPECT_EQ(row0.at(zero), 0.0) << zero;
        }
    }
}

TEST(InterfaceRun, ConstantNormalStressKeepsTnAndShearsAlongPlusT1) {
    for (const char* form : {"novel", "stutz"}) {
        const std::string file = test::write_scene(
            scene(std::string("formulation = \"") + form + "\"\nsubincrement = \"adaptive\""));
        const fs::path out = test::fresh_dir("iface-cnl");
        const Captured r = run_captured({"run", file, "--out", out.string(), "--quiet"});
        ASSERT_EQ(r.code, exit_code::ok) << r.err;
        const History h = read_history(out);
        for (const auto& row : h.rows) {
            EXPECT_EQ(row.at("t_n"), -100.0);
            // The sample carries t_N to the step's Newton tolerance (1e-4 relative).
            EXPECT_NEAR(row.at("sample_s11"), -100.0, 1e-2);
            EXPECT_NEAR(row.at("s_n"), -100.0, 1.0);
            // The plate's motion is the interface slip plus the sample's shear.
            EXPECT_GE(row.at("u_t1") + 1e-15, row.at("slip1"));
        }
        // The plate moving in +t1 against the soil: positive shear stress that grows, and the
        // interface strains and slips along +t1.
        const auto& last = h.rows.back();
        EXPECT_GT(last.at("t_t1"), 10.0) << form;
        EXPECT_GT(last.at("gamma1"), 0.0);
        EXPECT_GT(last.at("slip1"), 0.0);
        EXPECT_NE(last.at("u_n"), 0.0);
        EXPECT_EQ(last.at("t_t2"), 0.0);
    }
}

TEST(InterfaceRun, ConstantNormalStiffnessImposesTnMinusKUnOnTheSample) {
    // 400 kPa/mm = 4e5 kPa/m; compaction from the start of shearing moves t_n by K u_n.
    const std::string file =
        test::write_scene(scene(adaptive_novel,
                                "[normal]\ncontrol = \"constant-stiffness\"\nstiffness = 400.0\n"
                                "stiffness_unit = \"kPa/mm\"\n",
                                "[-300.0, -150.0, -150.0, 0.0, 0.0, 0.0]"));
    const fs::path out = test::fresh_dir("iface-cns");
    const Captured r = run_captured({"run", file, "--out", out.string(), "--quiet"});
    ASSERT_EQ(r.code, exit_code::ok) << r.err;
    const History h = read_history(out);
    double largest_change = 0.0;
    for (const auto& row : h.rows) {
        const double expected = -300.0 - 4.0e5 * row.at("u_n");
        EXPECT_NEAR(row.at("t_n"), expected, 1e-9 * 300.0);
        EXPECT_NEAR(row.at("sample_s11"), expected, 1.0001e-4 * std::abs(expected));
        largest_change = std::max(largest_change, std::abs(row.at("t_n") + 300.0));
    }
    // The stiffness matters: a kPa/m reading of 400 would move t_n 1000 times less.
    EXPECT_GT(largest_change, 1.0);
    const auto j = summary(out);
    EXPECT_EQ(j["normal_control"], "constant-stiffness");
    EXPECT_DOUBLE_EQ(j["normal_stiffness"].get<double>(), 4.0e5);
}

TEST(InterfaceRun, CoulombShearStaysInsideTheFrictionCone) {
    const double mu = 0.25;
    const std::string file = test::write_scene(
        scene("formulation = \"coulomb\"\nfriction_coefficient = 0.25\ntangential_stiffness = "
              "1.0e5",
              "", "[-100.0, -50.0, -60.0, 0.0, 0.0, 0.0]"));
    const fs::path out = test::fresh_dir("iface-coulomb");
    // 1 mm in 20 steps: the stick branch (0.25 mm to mu |t_N|) and then sliding.
    const Captured r = run_captured({"run", file, "--out", out.string(), "--quiet", "--set",
                                     "stage.1.steps=20", "--set", "stage.1.du_t1=0.001"});
    ASSERT_EQ(r.code, exit_code::ok) << r.err;
    const History h = read_history(out);
    ASSERT_EQ(h.rows.size(), 21u);
    double largest = 0.0;
    for (const auto& row : h.rows) {
        const double limit = mu * std::abs(row.at("t_n"));
        // t_t1 is the sample's s12, equal to the interface traction to the Newton tolerance.
        EXPECT_LE(std::abs(row.at("t_t1")), limit + 1e-4 * std::abs(row.at("t_n")))
            << "step " << row.at("step");
        largest = std::max(largest, row.at("t_t1"));
    }
    EXPECT_GT(largest, 0.99 * mu * 100.0); // the cone is reached, so the bound was tested
    // Stick: the first step's traction is k_t times the slip.
    EXPECT_NEAR(h.rows[1].at("t_t1"), 1.0e5 * h.rows[1].at("slip1"), 1e-4 * 100.0);
    const auto j = summary(out);
    EXPECT_EQ(j["formulation"], "coulomb");
    EXPECT_FALSE(j.contains("shear_band_thickness"));
}

TEST(InterfaceRun, SummaryHasInterfaceCountersAndPhases) {
    const std::string file = test::write_scene(scene(adaptive_novel));
    const fs::path out = test::fresh_dir("iface-summary");
    const Captured r = run_captured({"run", file, "--out", out.string(), "--threads", "1",
                                     "--quiet", "--set", "interface.roughness=0.8"});
    ASSERT_EQ(r.code, exit_code::ok) << r.err;
    const auto j = summary(out);
    EXPECT_EQ(j["kind"], "interface-test");
    EXPECT_EQ(j["status"], "ok");
    EXPECT_EQ(j["threads"], 1);
    EXPECT_EQ(j["formulation"], "novel");
    EXPECT_DOUBLE_EQ(j["roughness"].get<double>(), 0.8);
    EXPECT_EQ(j["rows"], 11);
    const auto& c = j["counters"];
    EXPECT_EQ(c["increments"], 10);
    EXPECT_GT(c["newton_iterations"].get<long>(), 0);
    EXPECT_GT(c["subincrements"].get<long>(), 0);
    EXPECT_GT(c["interface_newton_iterations"].get<long>(), 0);
    EXPECT_GT(c["sample_evaluations"].get<long>(), 0);
    // Eq. 37 lanes: every interface evaluation runs 7 lanes, so many more model calls.
    EXPECT_GT(c["interface_evaluations"].get<long>(), 7 * c["subincrements"].get<long>());
    EXPECT_EQ(c["constitutive_evaluations"].get<long>(),
              c["interface_evaluations"].get<long>() + c["sample_evaluations"].get<long>());
    for (const char* p : {"parse", "interface", "sample", "driver", "output"}) {
        ASSERT_TRUE(j["timing"]["phases"].contains(p)) << p;
        EXPECT_GE(j["timing"]["phases"][p].get<double>(), 0.0);
    }
    EXPECT_GT(j["timing"]["phases"]["interface"].get<double>(), 0.0);
}

// A run on a clamped shear band is "ok" but "degraded": summary.json says so with the count,
// stderr carries a warning even with --quiet; the same run without clamping is "clean".
TEST(InterfaceRun, ClampedBandMakesTheRunDegradedAndSaysSo) {
    const std::string file = test::write_scene(scene(adaptive_novel));
    const fs::path clean = test::fresh_dir("iface-clean");
    ASSERT_EQ(run_captured({"run", file, "--out", clean.string(), "--quiet"}).code, exit_code::ok);
    EXPECT_EQ(summary(clean)["quality"], "clean");
    EXPECT_TRUE(summary(clean)["warnings"].empty());
    const fs::path out = test::fresh_dir("iface-clamped");
    // Clamped as soon as the band compacts by 1e-4 of its thickness.
    const Captured r = run_captured({"run", file, "--out", out.string(), "--quiet", "--set",
                                     "integration.band_collapse=\"clamp\"", "--set",
                                     "integration.min_band_fraction=0.9999"});
    ASSERT_EQ(r.code, exit_code::ok) << r.err;
    const auto j = summary(out);
    EXPECT_EQ(j["status"], "ok");
    EXPECT_EQ(j["quality"], "degraded");
    ASSERT_EQ(j["warnings"].size(), 1u);
    EXPECT_EQ(j["warnings"][0]["code"], "band_clamped");
    EXPECT_EQ(j["warnings"][0]["count"].get<double>(),
              j["counters"]["band_clamped_steps"].get<double>());
    EXPECT_GT(j["warnings"][0]["count"].get<double>(), 0.0);
    EXPECT_NE(r.err.find("WARNING: degraded result"), std::string::npos) << r.err;
    // band_thickness is the thickness sheared at: the floor, not Eq. 26 below it (the
    // history once wrote d_s0 (1 + eps_N), negative in long compaction).
    const double d_s0 = j["shear_band_thickness"].get<double>();
    bool below_floor_by_eq26 = false;
    for (const auto& row : read_history(out).rows) {
        EXPECT_GE(row.at("band_thickness"), 0.9999 * d_s0 * (1.0 - 1e-12));
        below_floor_by_eq26 = below_floor_by_eq26 || (1.0 + row.at("eps_n") < 0.9999);
    }
    EXPECT_TRUE(below_floor_by_eq26);
}

TEST(InterfaceRun, ScalarAndSimdPathsAgreeToRoundOff) {
    const std::string file = test::write_scene(scene(adaptive_novel));
    const fs::path a = test::fresh_dir("iface-simd");
    const fs::path b = test::fresh_dir("iface-scalar");
    ASSERT_EQ(run_captured({"run", file, "--out", a.string()}).code, exit_code::ok);
    ASSERT_EQ(run_captured({"run", file, "--out", b.string(), "--scalar"}).code, exit_code::ok);
    const History ha = read_history(a);
    const History hb = read_history(b);
    ASSERT_EQ(ha.rows.size(), hb.rows.size());
    for (std::size_t i = 0; i < ha.rows.size(); ++i) {
        for (const char* k : {"t_t1", "u_n", "s_p1", "eps_n", "slip1"}) {
            const double x = ha.rows[i].at(k), y = hb.rows[i].at(k);
            EXPECT_NEAR(x, y, 1e-6 * std::max(1.0, std::abs(x))) << k << " row " << i;
        }
    }
    EXPECT_EQ(summary(b)["path"], "scalar");
}

TEST(InterfaceRun, FailedRunKeepsItsRowsAndSaysWhy) {
    // One Newton iteration cannot meet a 1e-14 residual: the first step fails for good.
    const std::string file =
        test::write_scene(scene(adaptive_novel) +
                          "[integration]\nnewton_tolerance = 1e-14\nmax_newton_iterations = 1\n");
    const fs::path out = test::fresh_dir("iface-failed");
    const Captured r = run_captured({"run", file, "--out", out.string()});
    EXPECT_EQ(r.code, exit_code::run_failed) << r.err;
    EXPECT_NE(r.err.find("run failed: step 1 (stage 1"), std::string::npos) << r.err;
    const auto j = summary(out);
    EXPECT_EQ(j["status"], "failed");
    EXPECT_NE(j["reason"].get<std::string>().find("Newton"), std::string::npos) << j["reason"];
    const History h = read_history(out);
    ASSERT_EQ(h.rows.size(), 1u); // step 0 only
    EXPECT_EQ(h.rows[0].at("t_n"), -100.0);
    EXPECT_FALSE(fs::exists(out / "history.csv.partial"));
}

TEST(InterfaceRun, BadInterfaceSceneIsABadInputWithFileAndKey) {
    const std::string file = test::write_scene(scene(adaptive_novel + "\nroughness = 1.5"));
    const fs::path out = test::fresh_dir("iface-bad");
    const Captured r = run_captured({"run", file, "--out", out.string()});
    EXPECT_EQ(r.code, exit_code::bad_input);
    EXPECT_NE(r.err.find(file), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("interface.roughness: expected a number in (0, 1]"), std::string::npos)
        << r.err;
    const auto j = summary(out);
    EXPECT_EQ(j["kind"], "interface-test");
    EXPECT_EQ(j["status"], "failed");
    EXPECT_FALSE(fs::exists(out / "history.csv"));

    const Captured s = run_captured({"run", test::write_scene(scene(adaptive_novel)), "--out",
                                     out.string(), "--set", "interface.friction_coefficient=0.3"});
    EXPECT_EQ(s.code, exit_code::bad_input);
    EXPECT_NE(s.err.find("(from --set interface.friction_coefficient=0.3)"), std::string::npos)
        << s.err;
}

} // namespace
} // namespace ifsim::io
