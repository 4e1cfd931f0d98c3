// Reading element-test scenes: the valid examples parse to the expected stages and states,
// and every class of bad input is a SceneError naming the file and the key.

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "io/element_test/element_test_scene.hpp"
#include "io/scene/scene_error.hpp"
#include "io/scene/scene_toml.hpp"
#include "tests/io/scene_test_support.hpp"

namespace ifsim::io {
namespace {

using test::write_scene;

ElementTestScene parse(const std::string& file) {
    return read_element_test_scene(load_scene_table(file), file);
}

// Parsing the scene text must fail with a SceneError for exactly this key whose message
// names the file and the key and contains `expected`.
void expect_error(const std::string& text, const std::string& key, const std::string& expected) {
    const std::string file = write_scene(text);
    try {
        parse(file);
        FAIL() << "no error for key " << key;
    } catch (const SceneError& e) {
        EXPECT_EQ(e.file(), file);
        EXPECT_EQ(e.key(), key) << e.what();
        const std::string what = e.what();
        EXPECT_NE(what.find(file), std::string::npos) << what;
        EXPECT_NE(what.find(key), std::string::npos) << what;
        EXPECT_NE(what.find(expected), std::string::npos) << what;
    }
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return text.replace(at, from.size(), to);
}

const std::string head = "kind = \"element-test\"\n";

TEST(SceneParsing, ExampleOedometerHasItsStagesAndState) {
    const ElementTestScene s = parse("scenes/element-hypo-oedometer.toml");
    EXPECT_EQ(s.material.model, "hypoplasticity");
    EXPECT_EQ(s.material.parameters, "karlsruhe-sand");
    ASSERT_EQ(s.stages.size(), 3u);
    EXPECT_EQ(s.stages[0].steps, 1000);
    EXPECT_EQ(s.stages[1].steps, 500);
    EXPECT_DOUBLE_EQ(s.stages[0].change[0], -0.01);
    EXPECT_DOUBLE_EQ(s.stages[1].change[0], 0.002);
    for (const auto& st : s.stages) {
        for (bool stress : st.stress_controlled) {
            EXPECT_FALSE(stress);
        }
    }
    ASSERT_EQ(s.initial_state.size(), static_cast<std::size_t>(Hypoplasticity::n_state));
    EXPECT_DOUBLE_EQ(s.initial_state[0], -50.0);
    EXPECT_DOUBLE_EQ(s.initial_state[1], -25.0);
    EXPECT_DOUBLE_EQ(s.initial_state[6], 0.70);
    EXPECT_EQ(s.total_steps(), 2500);
}

TEST(SceneParsing, ExampleTriaxialHoldsTheLateralStresses) {
    const ElementTestScene s = parse("scenes/element-hypo-triaxial-drained-dense.toml");
    ASSERT_EQ(s.stages.size(), 1u);
    const ElementStage& st = s.stages[0];
    EXPECT_FALSE(st.stress_controlled[0]);
    EXPECT_TRUE(st.stress_controlled[1]);
    EXPECT_TRUE(st.stress_controlled[2]);
    EXPECT_FALSE(st.stress_controlled[3]);
    EXPECT_DOUBLE_EQ(st.change[0], -0.20);
    EXPECT_DOUBLE_EQ(st.change[1], 0.0);
}

TEST(SceneParsing, ExampleSimpleShearControlsNormalStressAndShearStrain) {
    for (const char* f :
         {"scenes/element-hypo-simple-shear.toml", "scenes/element-sanisand-simple-shear.toml"}) {
        const ElementTestScene s = parse(f);
        const ElementStage& st = s.stages.at(0);
        EXPECT_TRUE(st.stress_controlled[0]) << f;
        EXPECT_FALSE(st.stress_controlled[1]) << f;
        EXPECT_FALSE(st.stress_controlled[3]) << f;
        EXPECT_GT(st.change[3], 0.0) << f;
    }
}

TEST(SceneParsing, UndrainedExamplesAreIsochoric) {
    for (const char* f : {"scenes/element-hypo-triaxial-undrained.toml",
                          "scenes/element-hypo-cyclic-undrained.toml",
                          "scenes/element-sanisand-triaxial-undrained.toml",
                          "scenes/element-sanisand-cyclic-undrained.toml"}) {
        const ElementTestScene s = parse(f);
        for (const auto& st : s.stages) {
            EXPECT_NEAR(st.change[0] + st.change[1] + st.change[2], 0.0, 1e-15) << f;
            EXPECT_DOUBLE_EQ(st.change[1], st.change[2]) << f;
        }
    }
}

TEST(SceneParsing, EveryExampleSceneParses) {
    int n = 0;
    for (const auto& entry : std::filesystem::directory_iterator("scenes")) {
        const std::string name = entry.path().filename().string();
        if (entry.path().extension() != ".toml" || !name.starts_with("element-")) {
            continue;
        }
        ++n;
        EXPECT_NO_THROW(parse(entry.path().string())) << name;
    }
    EXPECT_GE(n, 12);
}

TEST(SceneParsing, SanisandDefaultsPutTheBackStressOnTheConeAxis) {
    const std::string text = head + R"(
[material]
model = "sanisand"
parameters = "karlsruhe-sand"
[initial]
stress = [-100.0, -50.0, -50.0, 0.0, 0.0, 0.0]
void_ratio = 0.75
)" + test::oedometer_stage;
    const ElementTestScene s = parse(write_scene(text));
    ASSERT_EQ(s.initial_state.size(), 25u);
    const double alpha[6] = {0.5, -0.25, -0.25, 0.0, 0.0, 0.0};
    for (int i = 0; i < 6; ++i) {
        EXPECT_NEAR(s.initial_state[7 + i], alpha[i], 1e-15) << i;  // alpha
        EXPECT_EQ(s.initial_state[13 + i], 0.0) << i;               // z
        EXPECT_NEAR(s.initial_state[19 + i], alpha[i], 1e-15) << i; // alpha_in
    }
}

TEST(SceneParsing, SanisandTakesAGivenBackStressAndFabric) {
    const std::string text = head + R"(
[material]
model = "sanisand"
parameters = "karlsruhe-sand"
[initial]
stress = [-100.0, -50.0, -50.0, 0.0, 0.0, 0.0]
void_ratio = 0.75
back_stress = [0.48, -0.24, -0.24, 0.0, 0.0, 0.0]
fabric = [1.0, -0.5, -0.5, 0.0, 0.0, 0.0]
)" + test::oedometer_stage;
    const ElementTestScene s = parse(write_scene(text));
    EXPECT_DOUBLE_EQ(s.initial_state[7], 0.48);
    EXPECT_DOUBLE_EQ(s.initial_state[13], 1.0);
    EXPECT_DOUBLE_EQ(s.initial_state[19], 0.48);
}

TEST(SceneParsing, InlineParametersUseDegreesAndRoughnessReachesTheModel) {
    const std::string text = head + R"(
[material]
model = "hypoplasticity"
roughness = 0.8
intergranular_strain = false
[material.parameters]
phi_c = 33.1
h_s = 19.0e6
n = 0.285
e_i0 = 0.979
e_c0 = 0.851
e_d0 = 0.549
alpha = 0.1
beta = 0.32
m_R = 2.4
m_T = 1.2
R = 5.0e-5
beta_R = 0.08
chi = 7
)" + test::hypo_initial + test::oedometer_stage;
    const ElementTestScene s = parse(write_scene(text));
    const auto& p = std::get<HypoplasticityParams>(s.material.choice);
    EXPECT_NEAR(p.phi_c, 33.1 * std::numbers::pi / 180.0, 1e-15);
    EXPECT_DOUBLE_EQ(p.chi, 7.0);
    EXPECT_DOUBLE_EQ(p.roughness, 0.8);
    EXPECT_FALSE(p.intergranular_strain);
    EXPECT_GT(p.a, 0.0); // prepare() ran
    EXPECT_EQ(s.material.parameters, "inline");
}

TEST(SceneParsing, LinearElasticNeedsItsTwoConstants) {
    const std::string ok = head + R"(
[material]
model = "linear-elastic"
parameters = { E = 50000.0, nu = 0.3 }
[initial]
stress = [10.0, 0.0, 0.0, 0.0, 0.0, 0.0]
void_ratio = 0.7
)" + test::oedometer_stage;
    const ElementTestScene s = parse(write_scene(ok));
    EXPECT_EQ(s.initial_state.size(), 7u);
    EXPECT_DOUBLE_EQ(std::get<LinearElasticParams>(s.material.choice).E, 50000.0);
    expect_error(replaced(ok, "E = 50000.0, ", ""), "material.parameters.E", "missing");
}

TEST(SceneParsing, IntegrationSettingsAreRead) {
    const std::string text = test::valid_scene() + R"(
[integration]
tolerance = 1.0e-4
tangent = "rate"
newton_tolerance = 1.0e-10
max_newton_iterations = 30
)";
    const ElementTestScene s = parse(write_scene(text));
    EXPECT_DOUBLE_EQ(s.settings.update.settings.tolerance, 1.0e-4);
    EXPECT_EQ(s.settings.tangent, TangentKind::rate);
    EXPECT_DOUBLE_EQ(s.settings.newton_tolerance, 1.0e-10);
    EXPECT_EQ(s.settings.max_newton_iterations, 30);
}

// --- errors ---------------------------------------------------------------------------

TEST(SceneErrors, UnknownKeysAnywhere) {
    expect_error("colour = 1\n" + test::valid_scene(), "colour", "unknown key");
    expect_error(replaced(test::valid_scene(), "model = \"hypoplasticity\"",
                          "model = \"hypoplasticity\"\nx = 1"),
                 "material.x", "unknown key");
    expect_error(replaced(test::valid_scene(), "parameters = \"karlsruhe-sand\"",
                          "parameters = \"karlsruhe-sand\"\nrougness = 0.5"),
                 "material.rougness", "unknown key");
    expect_error(replaced(test::valid_scene(), "void_ratio = 0.7", "void_ratio = 0.7\nvoid = 1"),
                 "initial.void", "unknown key");
    expect_error(replaced(test::valid_scene(), "steps = 10", "steps = 10\nsteps_x = 1"),
                 "stage.2.steps_x", "unknown key");
    expect_error(test::valid_scene() + "[integration]\ntol = 1e-4\n", "integration.tol",
                 "unknown key");
}

TEST(SceneErrors, WrongTypes) {
    expect_error(replaced(test::valid_scene(), "void_ratio = 0.7", "void_ratio = \"dense\""),
                 "initial.void_ratio", "expected a number > 0, got a string");
    expect_error(replaced(test::valid_scene(), "steps = 20", "steps = 20.0"), "stage.1.steps",
                 "expected an integer");
    expect_error(replaced(test::valid_scene(), "model = \"hypoplasticity\"", "model = 3"),
                 "material.model", "expected one of");
    expect_error(replaced(test::valid_scene(), "stress = [-100.0, -50.0, -50.0, 0.0, 0.0, 0.0]",
                          "stress = [-100.0, -50.0, -50.0, 0.0, 0.0]"),
                 "initial.stress", "an array of 6 finite numbers");
    expect_error(replaced(test::valid_scene(), "stress = [-100.0, -50.0, -50.0, 0.0, 0.0, 0.0]",
                          "stress = [-100.0, -50.0, \"x\", 0.0, 0.0, 0.0]"),
                 "initial.stress.3", "expected a finite number");
    expect_error(head + "stage = 5\n" + test::hypo_material + test::hypo_initial, "stage",
                 "one or more tables [[stage]], got an integer 5");
}

TEST(SceneErrors, MissingRequiredKeys) {
    expect_error(replaced(test::valid_scene(), "void_ratio = 0.7", ""), "initial.void_ratio",
                 "missing");
    expect_error(replaced(test::valid_scene(), "steps = 20", ""), "stage.1.steps", "missing");
    expect_error(replaced(test::valid_scene(), "parameters = \"karlsruhe-sand\"", ""),
                 "material.parameters", "missing");
    expect_error(head + test::hypo_material + test::hypo_initial, "stage", "missing");
    expect_error(head + test::hypo_initial + test::oedometer_stage, "material", "missing");
}

TEST(SceneErrors, OutOfRangeAndNonFiniteValues) {
    expect_error(replaced(test::valid_scene(), "steps = 20", "steps = -5"), "stage.1.steps",
                 "an integer from 1");
    expect_error(replaced(test::valid_scene(), "steps = 20", "steps = 0"), "stage.1.steps",
                 "an integer from 1");
    expect_error(replaced(test::valid_scene(), "void_ratio = 0.7", "void_ratio = 0.0"),
                 "initial.void_ratio", "> 0");
    expect_error(replaced(test::valid_scene(), "void_ratio = 0.7", "void_ratio = -0.1"),
                 "initial.void_ratio", "> 0");
    expect_error(replaced(test::valid_scene(), "void_ratio = 0.7", "void_ratio = nan"),
                 "initial.void_ratio", "got a number nan");
    expect_error(replaced(test::valid_scene(), "deps_11 = -0.001", "deps_11 = inf"),
                 "stage.1.deps_11", "finite");
    expect_error(replaced(test::valid_scene(), "stress = [-100.0,", "stress = [-inf,"),
                 "initial.stress.1", "finite");
    const std::string rough = replaced(test::valid_scene(), "parameters = \"karlsruhe-sand\"",
                                       "parameters = \"karlsruhe-sand\"\nroughness = RHO");
    expect_error(replaced(rough, "RHO", "0.0"), "material.roughness", "in (0, 1]");
    expect_error(replaced(rough, "RHO", "1.5"), "material.roughness", "in (0, 1]");
    expect_error(test::valid_scene() + "[integration]\ntangent = \"secant\"\n",
                 "integration.tangent", "\"perturbation\" | \"rate\"");
}

TEST(SceneErrors, EachComponentNeedsExactlyOneControl) {
    expect_error(replaced(test::valid_scene(), "dsig_22 = 0.0", "dsig_22 = 0.0\ndeps_22 = 0.0"),
                 "stage.2", "component 22: expected exactly one of deps_22");
    const std::string neither =
        replaced(test::valid_scene(), "deps_13 = 0.0\ndeps_23 = 0.0\n\n[[stage]]",
                 "deps_23 = 0.0\n\n[[stage]]");
    expect_error(neither, "stage.1",
                 "component 13: expected exactly one of deps_13 (change of "
                 "the strain over the stage) and dsig_13");
    expect_error(neither, "stage.1", "found neither");
}

TEST(SceneErrors, ParameterSets) {
    expect_error(replaced(test::valid_scene(), "\"karlsruhe-sand\"", "\"ottawa\""),
                 "material.parameters", "no built-in hypoplasticity parameter set \"ottawa\"");
    const std::string inline_missing = head + R"(
[material]
model = "hypoplasticity"
[material.parameters]
phi_c = 33.1
h_s = 19.0e6
)" + test::hypo_initial + test::oedometer_stage;
    expect_error(inline_missing, "material.parameters.n", "missing");
    const std::string inline_unknown =
        replaced(inline_missing, "h_s = 19.0e6", "h_s = 19.0e6\nhs = 1.0");
    expect_error(inline_unknown, "material.parameters.hs", "unknown key");
    const std::string bad_angle = replaced(inline_missing, "phi_c = 33.1", "phi_c = 0.58");
    const std::string full = R"(n = 0.285
e_i0 = 0.979
e_c0 = 0.851
e_d0 = 0.549
alpha = 0.1
beta = 0.32
m_R = 2.4
m_T = 1.2
R = 5.0e-5
beta_R = 0.08
chi = 7
)";
    EXPECT_NO_THROW(
        parse(write_scene(replaced(bad_angle, "h_s = 19.0e6\n", "h_s = 19.0e6\n" + full))));
    expect_error(replaced(replaced(inline_missing, "h_s = 19.0e6\n", "h_s = 19.0e6\n" + full),
                          "e_c0 = 0.851", "e_c0 = 0.5"),
                 "material.parameters.e_c0", "e_d0 < e_c0 < e_i0");
}

TEST(SceneErrors, ModelSpecificStateKeysBelongToTheirModel) {
    expect_error(replaced(test::valid_scene(), "void_ratio = 0.7",
                          "void_ratio = 0.7\nback_stress = [0.5, -0.25, -0.25, 0, 0, 0]"),
                 "initial.back_stress", "sanisand only");
    const std::string sanisand = head + R"(
[material]
model = "sanisand"
parameters = "karlsruhe-sand"
[initial]
stress = [-100.0, -50.0, -50.0, 0.0, 0.0, 0.0]
void_ratio = 0.75
)" + test::oedometer_stage;
    expect_error(replaced(sanisand, "void_ratio = 0.75",
                          "void_ratio = 0.75\nintergranular_strain = [0, 0, 0, 0, 0, 0]"),
                 "initial.intergranular_strain", "hypoplasticity only");
    expect_error(replaced(sanisand, "parameters = \"karlsruhe-sand\"",
                          "parameters = \"karlsruhe-sand\"\nintergranular_strain = true"),
                 "material.intergranular_strain", "hypoplasticity only");
}

TEST(SceneErrors, InadmissibleInitialStates) {
    // Tension for a granular model.
    expect_error(replaced(test::valid_scene(), "stress = [-100.0, -50.0, -50.0,",
                          "stress = [100.0, 50.0, 50.0,"),
                 "initial.stress", "compressive stress state");
    // Looser than e_i at 100 kPa (about 0.94) and denser than e_d (about 0.53).
    expect_error(replaced(test::valid_scene(), "void_ratio = 0.7", "void_ratio = 1.2"),
                 "initial.void_ratio", "between e_d");
    expect_error(replaced(test::valid_scene(), "void_ratio = 0.7", "void_ratio = 0.4"),
                 "initial.void_ratio", "between e_d");
    // |h| > R = 5e-5.
    expect_error(replaced(test::valid_scene(), "void_ratio = 0.7",
                          "void_ratio = 0.7\nintergranular_strain = [-1e-4, 0, 0, 0, 0, 0]"),
                 "initial.intergranular_strain", "|h| <= R");
    // A back stress far from the stress ratio: outside the yield cone.
    const std::string sanisand = head + R"(
[material]
model = "sanisand"
parameters = "karlsruhe-sand"
[initial]
stress = [-100.0, -50.0, -50.0, 0.0, 0.0, 0.0]
void_ratio = 0.75
back_stress = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
)" + test::oedometer_stage;
    expect_error(sanisand, "initial.back_stress", "outside the yield surface");
    expect_error(
        replaced(sanisand, "[0.0, 0.0, 0.0, 0.0, 0.0, 0.0]", "[0.5, -0.25, -0.2, 0.0, 0.0, 0.0]"),
        "initial.back_stress", "deviatoric");
}

TEST(SceneErrors, FileLevelProblems) {
    const std::string missing = "/nonexistent/dir/scene.toml";
    try {
        load_scene_table(missing);
        FAIL();
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find(missing), std::string::npos);
    }
    const std::string broken = write_scene("kind = \"element-test\"\n[material\nmodel = 1\n");
    try {
        load_scene_table(broken);
        FAIL();
    } catch (const SceneError& e) {
        EXPECT_EQ(e.file(), broken);
        EXPECT_EQ(e.line(), 2);
        EXPECT_NE(std::string(e.what()).find("not valid TOML"), std::string::npos);
    }
}

TEST(SceneErrors, KindIsRequiredAndAString) {
    const std::string no_kind = write_scene(test::hypo_material);
    EXPECT_THROW(scene_kind(load_scene_table(no_kind), no_kind), SceneError);
    const std::string number = write_scene("kind = 3\n");
    try {
        scene_kind(load_scene_table(number), number);
        FAIL();
    } catch (const SceneError& e) {
        EXPECT_EQ(e.key(), "kind");
        EXPECT_EQ(e.line(), 1);
    }
    const std::string other = write_scene("kind = \"interface-test\"\n");
    EXPECT_EQ(scene_kind(load_scene_table(other), other), "interface-test");
}

TEST(SceneErrors, MessagesGiveTheLineOfTheValue) {
    const std::string file =
        write_scene(replaced(test::valid_scene(), "void_ratio = 0.7", "void_ratio = -1.0"));
    try {
        parse(file);
        FAIL();
    } catch (const SceneError& e) {
        EXPECT_EQ(e.line(), 9); // line of void_ratio in valid_scene()
        EXPECT_NE(std::string(e.what()).find(file + ":9: initial.void_ratio"), std::string::npos)
            << e.what();
    }
}

} // namespace
} // namespace ifsim::io
