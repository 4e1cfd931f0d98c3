// Runs whose states leave the region where the models describe sand say so (summary.json
// "degraded" with a warning naming rows and steps), and a band that cannot meet its targets
// fails with the cause, a true number and the reason when it is known.

#include <filesystem>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "engine/state_admissibility.hpp"
#include "io/cli/exit_codes.hpp"
#include "tests/io/scene_test_support.hpp"

namespace ifsim::io {
namespace {

namespace fs = std::filesystem;

nlohmann::json summary(const fs::path& dir) {
    return nlohmann::json::parse(test::read_text(dir / "summary.json"));
}

// Drained axial extension from 1 kPa with the lateral stress held: both models' converged
// answers pass through a tensile axial stress (Sanisand +0.13 kPa, hypoplasticity +0.017 kPa,
// unchanged at integration tolerance 1e-6 and 100x the steps).
std::string extension_scene(const std::string& model) {
    return "kind = \"element-test\"\n[material]\nmodel = \"" + model +
           "\"\nparameters = \"karlsruhe-sand\"\n[initial]\nstress = [-1.0, -1.0, -1.0, 0.0, "
           "0.0, 0.0]\nvoid_ratio = 0.7\n[[stage]]\nsteps = 200\ndeps_11 = 0.05\ndsig_22 = "
           "0.0\ndsig_33 = 0.0\ndeps_12 = 0.0\ndeps_13 = 0.0\ndeps_23 = 0.0\n";
}

TEST(Admissibility, TensileStressOfAnExtensionMakesTheRunDegraded) {
    for (const std::string model : {"sanisand", "hypoplasticity"}) {
        const fs::path out = test::fresh_dir("adm-ext-" + model);
        const auto r = test::run_cli_captured(
            {"run", test::write_scene(extension_scene(model)), "--out", out.string(), "-q"});
        ASSERT_EQ(r.code, exit_code::ok) << r.err;
        const auto j = summary(out);
        EXPECT_EQ(j["status"], "ok");
        EXPECT_EQ(j["quality"], "degraded") << model;
        ASSERT_FALSE(j["warnings"].empty());
        EXPECT_EQ(j["warnings"][0]["code"], "material_tension");
        const auto& t = j["admissibility"]["material"]["tension"];
        EXPECT_GT(t["rows"].get<long>(), 0);
        EXPECT_GT(t["worst"].get<double>(), tension_tolerance);
        EXPECT_GE(t["worst_step"].get<int>(), t["first_step"].get<int>());
        EXPECT_NE(r.err.find("tensile principal stress"), std::string::npos) << r.err;
    }
}

// The same drained path under compression stays clean: the check is not a blanket warning.
TEST(Admissibility, DrainedCompressionStaysClean) {
    std::string scene = extension_scene("hypoplasticity");
    scene.replace(scene.find("deps_11 = 0.05"), 14, "deps_11 = -0.05");
    const fs::path out = test::fresh_dir("adm-comp");
    const auto r =
        test::run_cli_captured({"run", test::write_scene(scene), "--out", out.string(), "-q"});
    ASSERT_EQ(r.code, exit_code::ok) << r.err;
    const auto j = summary(out);
    EXPECT_EQ(j["quality"], "clean") << j["warnings"].dump();
    EXPECT_EQ(j["admissibility"]["material"]["tension"]["rows"].get<long>(), 0);
    EXPECT_EQ(j["admissibility"]["material"]["void_ratio"]["rows"].get<long>(), 0);
}

// Hypoplasticity's bounds: isotropic compression from e = e_i(p) (the reader's upper limit).
// With intergranular strain starting at h = 0 the first strains meet the stiffer response
// (m_R), p rises faster than e falls and the state passes e_i(p) (by 0.015 here): the model's
// own answer, counted.
TEST(Admissibility, VoidRatioPastTheBauerBoundIsCounted) {
    const HypoplasticityParams p = *parameter_sets::hypoplasticity("karlsruhe-sand");
    const double e_i = p.e_i0 * std::exp(-std::pow(300.0 / p.h_s, p.n));
    std::string scene = extension_scene("hypoplasticity");
    scene.replace(scene.find("[-1.0, -1.0, -1.0"), 17, "[-100.0, -100.0, -100.0");
    scene.replace(scene.find("void_ratio = 0.7"), 16, fmt::format("void_ratio = {}", e_i));
    scene.replace(scene.find("deps_11 = 0.05"), 14, "deps_11 = -0.02");
    scene.replace(scene.find("dsig_22 = 0.0"), 13, "deps_22 = -0.02");
    scene.replace(scene.find("dsig_33 = 0.0"), 13, "deps_33 = -0.02");
    const fs::path out = test::fresh_dir("adm-void");
    const auto r =
        test::run_cli_captured({"run", test::write_scene(scene), "--out", out.string(), "-q"});
    ASSERT_EQ(r.code, exit_code::ok) << r.err;
    const auto j = summary(out);
    const auto& v = j["admissibility"]["material"]["void_ratio"];
    EXPECT_GT(v["rows"].get<long>(), 0) << j.dump();
    EXPECT_EQ(j["quality"], "degraded");
    EXPECT_LT(v["worst"].get<double>(), 0.05);
}

// The Matsuoka-Nakai limit of kappa phi_c: a triaxial compression state at
// sigma_1 / sigma_3 = (1 + sin phi) / (1 - sin phi) lies on it; 1 % more lies outside.
TEST(Admissibility, MatsuokaNakaiLimitMatchesTheTriaxialFrictionAngle) {
    HypoplasticityParams p = *parameter_sets::hypoplasticity("l4c");
    for (const double kappa : {1.0, 0.6, 0.05}) {
        p.roughness = kappa;
        p.prepare();
        const double s = std::sin(kappa * p.phi_c);
        const double ratio = (1.0 + s) / (1.0 - s);
        const auto on =
            Hypoplasticity::matsuoka_nakai(p, {-100.0 * ratio, -100.0, -100.0, 0, 0, 0});
        EXPECT_NEAR(on.value, on.limit, 1e-9 * on.limit) << kappa;
        const auto out =
            Hypoplasticity::matsuoka_nakai(p, {-101.0 * ratio, -100.0, -100.0, 0, 0, 0});
        EXPECT_TRUE(out.outside()) << kappa;
    }
}

// kappa = 0.05 with the novel formulation cannot carry the continuum's sigma_p = sigma_N / 2:
// the run stops at step 1 naming the limit surface, with a residual that is not 0.
TEST(Admissibility, SmoothNovelBandStopsWithTheTrueCause) {
    const fs::path out = test::fresh_dir("adm-kappa");
    const auto r =
        test::run_cli_captured({"run", "scenes/simple-shear-cnl.toml", "--out", out.string(), "-q",
                                "--set", "interface.roughness=0.05", "--set",
                                "interface.subincrement=adaptive", "--set", "stage.1.steps=10"});
    ASSERT_EQ(r.code, exit_code::run_failed) << r.err;
    const std::string reason = summary(out)["reason"];
    EXPECT_NE(reason.find("step 1 "), std::string::npos) << reason;
    EXPECT_NE(reason.find("outside the interface model's limit surface"), std::string::npos)
        << reason;
    EXPECT_EQ(reason.find("residual 0)"), std::string::npos) << reason;
}

// The per-step work bound of interface tests stops the run at once, naming step and bound (no
// cutting of the step: a cut redoes the same work).
TEST(Admissibility, StepWorkBoundStopsTheRunNamingIt) {
    const fs::path out = test::fresh_dir("adm-bound");
    const auto r = test::run_cli_captured(
        {"run", "scenes/simple-shear-cnl.toml", "--out", out.string(), "-q", "--set",
         "interface.subincrement=adaptive", "--set", "integration.max_step_substeps=5"});
    ASSERT_EQ(r.code, exit_code::run_failed) << r.err;
    const std::string reason = summary(out)["reason"];
    EXPECT_NE(reason.find("step 1 "), std::string::npos) << reason;
    EXPECT_NE(reason.find("max_step_substeps"), std::string::npos) << reason;
    EXPECT_EQ(reason.find("cutting"), std::string::npos) << reason;
}

// The FE solver's bound per nominal step and contact point: the shear box's first shear step
// needs about 3000 substeps per point; a bound of 100 stops it there, without cuts, and the
// consolidation stage before it (no shear, few substeps) completes.
TEST(Admissibility, FeStepWorkBoundStopsTheStageNamingIt) {
    const fs::path out = test::fresh_dir("adm-fe-bound");
    const auto r =
        test::run_cli_captured({"run", "scenes/fe-simple-shear-cnl-2d.toml", "--out", out.string(),
                                "-q", "--set", "solver.max_step_substeps=100"});
    ASSERT_EQ(r.code, exit_code::run_failed) << r.err;
    const auto j = summary(out);
    const std::string reason = j["reason"];
    EXPECT_NE(reason.find("stage 2 ('shear'), step 1 of"), std::string::npos) << reason;
    EXPECT_NE(reason.find("max_step_substeps"), std::string::npos) << reason;
    EXPECT_EQ(reason.find("halving"), std::string::npos) << reason;
    EXPECT_EQ(j["counters"]["cuts"], 0);
}

} // namespace
} // namespace ifsim::io
