// Replay scenes read back exactly what was written: an interface-point scene gives the recorded
// call's state, inputs and every Algorithm 1 option bit for bit; an element-test replay of a
// step in the middle of a stage (its stress targets and Newton guess) computes the state the
// run computed for that step.

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "engine/element_test_driver.hpp"
#include "io/element_test/element_test_scene.hpp"
#include "io/interface_point/algorithm1_options.hpp"
#include "io/interface_point/interface_point_scene.hpp"
#include "io/replay/element_replay.hpp"
#include "io/replay/interface_replay.hpp"
#include "io/scene/scene_toml.hpp"

namespace ifsim::io {
namespace {

std::string text_of(const toml::table& t) {
    std::ostringstream s;
    s << t;
    return s.str();
}

bool same_bits(double a, double b) {
    return std::memcmp(&a, &b, sizeof a) == 0;
}

// An interface test scene's [interface] table with inline parameters, read as a MaterialSpec.
MaterialSpec inline_sanisand(double roughness) {
    const toml::table t = parse_scene_text(
        "model = \"sanisand\"\n[parameters]\np_a = 101.3\ne0 = 0.934\nlambda_c = 0.019\nxi = "
        "0.7\nM_c = 1.25\nc = 0.712\nm = 0.01\nG0 = 125.0\nnu = 0.05\nh0 = 7.05\nc_h = 0.968\n"
        "n_b = 1.1\nA0 = 0.704\nn_d = 3.5\nz_max = 4.0\nc_z = 600.0\n",
        "inline.toml");
    return read_model_and_parameters(TableReader(t, "inline.toml", "interface"), "sanisand", true,
                                     roughness);
}

TEST(ReplayScenes, InterfacePointSceneGivesBackTheCallBitForBit) {
    FailedContactPoint p;
    p.model = "sanisand";
    p.ndim = 2;
    const MaterialSpec material = inline_sanisand(0.7);
    const int ns = state_size(material.choice);
    for (int k = 0; k < ns + contact_state::n_extra; ++k) {
        p.state.push_back(1.0 / 3.0 + 0.1 * k - (k == 0 ? 200.0 : 0.0));
    }
    for (std::size_t k = 0; k < p.inputs.size(); ++k) {
        p.inputs[k] = -0.1 / (1.0 + static_cast<double>(k));
    }
    p.inputs[contact_col::k_N] = 1.0e5 / 3.0; // a penalty is >= 0
    p.inputs[contact_col::forced] = 7.0;      // a count of equal sub-increments
    // Options away from their defaults, every kind of field.
    p.options.interface.formulation = InterfaceFormulation::stutz;
    p.options.interface.ndim = 2;
    p.options.interface.tolerance = 1.2345e-4;
    p.options.interface.adaptive = true;
    p.options.interface.max_subincrements = 12345;
    p.options.interface.newton_jacobian = NewtonJacobian::perturbation;
    p.options.interface.clamp_band = true;
    p.options.interface.max_normal_change = 0.03;
    p.options.interface.model.scheme = IntegrationScheme::rkf23;
    p.options.interface.model.carry_substep = true;
    p.options.interface.model.max_substeps = 777;
    p.options.jacobian = ContactJacobian::central;
    p.options.perturbation = 3.0e-9;

    const std::string text = text_of(interface_replay_scene(p, material, "test"));
    const InterfacePointScene back =
        read_interface_point_scene(parse_scene_text(text, "replay.toml"), "replay.toml");
    EXPECT_EQ(back.material.model, "sanisand");
    EXPECT_EQ(back.material.parameters, "inline");
    EXPECT_TRUE(same_bits(back.material.roughness, 0.7));
    EXPECT_EQ(back.point.ndim, 2);
    ASSERT_EQ(back.point.state.size(), p.state.size());
    for (std::size_t k = 0; k < p.state.size(); ++k) {
        EXPECT_TRUE(same_bits(back.point.state[k], p.state[k])) << k;
    }
    for (std::size_t k = 0; k < p.inputs.size(); ++k) {
        EXPECT_TRUE(same_bits(back.point.inputs[k], p.inputs[k])) << k;
    }
    EXPECT_EQ(back.point.options.interface.formulation, InterfaceFormulation::stutz);
    EXPECT_EQ(text_of(algorithm1_table(back.point.options)), text_of(algorithm1_table(p.options)));
    EXPECT_NE(text_of(algorithm1_table(back.point.options)),
              text_of(algorithm1_table(ContactOptions{})));
}

// A call with a non-finite input (cause "non-finite input") has no scene: writing its replay
// throws, and the run turns that into the warning replay_not_written.
TEST(ReplayScenes, NonFiniteCallIsNotWritten) {
    FailedContactPoint p;
    const MaterialSpec material = inline_sanisand(0.9);
    p.state.assign(static_cast<std::size_t>(state_size(material.choice) + contact_state::n_extra),
                   -1.0);
    p.inputs.fill(0.0);
    p.inputs[contact_col::dg1] = std::numeric_limits<double>::quiet_NaN();
    const auto dir = std::filesystem::temp_directory_path();
    EXPECT_THROW(write_interface_replay(dir, p, material, "test", true), std::runtime_error);
    p.inputs[contact_col::dg1] = 0.0;
    p.state[3] = std::numeric_limits<double>::infinity();
    EXPECT_THROW(write_interface_replay(dir, p, material, "test", true), std::runtime_error);
}

// A drained triaxial stage of 10 steps; the replay of its 6th step from the position after the
// 5th (mid-stage: stress targets reached from the stage's start, the Newton guess carried).
TEST(ReplayScenes, ElementReplayOfAMidStageStepComputesTheRunsStep) {
    const std::string scene_text =
        "kind = \"element-test\"\n[material]\nmodel = \"hypoplasticity\"\nparameters = "
        "\"karlsruhe-sand\"\n[initial]\nstress = [-100.0, -100.0, -100.0, 0.0, 0.0, 0.0]\n"
        "void_ratio = 0.65\n[[stage]]\nsteps = 10\ndeps_11 = -0.01\ndsig_22 = -30.0\n"
        "dsig_33 = 0.0\ndeps_12 = 0.0\ndeps_13 = 0.0\ndeps_23 = 0.0\n";
    const toml::table table = parse_scene_text(scene_text, "scene.toml");
    const ElementTestScene scene = read_element_test_scene(table, "scene.toml");
    std::vector<std::vector<double>> rows;
    std::vector<ElementTestPosition> positions;
    const ElementTestResult r = run_element_test(
        scene.material.choice, scene.initial_state, scene.stages, scene.settings,
        [&](const ElementRow& row) { rows.push_back(row.state); }, nullptr,
        [&](const ElementTestPosition& p) { positions.push_back(p); });
    ASSERT_TRUE(r.ok) << r.reason;
    ASSERT_EQ(positions.size(), 10u);

    ElementRunOutcome failed;
    failed.point_failed = true;
    failed.last = positions[4]; // after step 5
    failed.result.reason = "test";
    const std::string replay_text = text_of(element_replay_scene(table, scene, failed));
    const toml::table replay_table = parse_scene_text(replay_text, "replay.toml");
    const ElementTestScene replay = read_element_test_scene(replay_table, "replay.toml");
    ASSERT_EQ(replay.stages.size(), 1u);
    EXPECT_EQ(replay.stages[0].steps, 1);
    EXPECT_NE(replay.stages[0].first_guess[1], 0.0); // the lateral strain guess of step 6
    std::vector<std::vector<double>> replay_rows;
    const ElementTestResult rr = run_element_test(
        replay.material.choice, replay.initial_state, replay.stages, replay.settings,
        [&](const ElementRow& row) { replay_rows.push_back(row.state); });
    ASSERT_TRUE(rr.ok) << rr.reason;
    ASSERT_EQ(replay_rows.size(), 2u);
    // Row 0 of the replay is the run's row 5 exactly; row 1 its row 6 (the stress target is
    // rebuilt as sigma + (target - sigma), within an ulp of the run's).
    for (std::size_t k = 0; k < rows[5].size(); ++k) {
        EXPECT_TRUE(same_bits(replay_rows[0][k], rows[5][k])) << k;
        EXPECT_NEAR(replay_rows[1][k], rows[6][k], 1e-9 * (1.0 + std::abs(rows[6][k]))) << k;
    }
    EXPECT_NEAR(replay_rows[1][1], -100.0 - 30.0 * 6 / 10, 1e-6); // the stage's target
}

} // namespace
} // namespace ifsim::io
