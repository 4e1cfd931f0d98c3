// Reading interface-test scenes: the contract's example parses to its values, left-out keys take
// the contract's defaults, the initial interface stress follows the formulation, --set reaches
// interface keys, and every class of bad input is a SceneError naming the file and the key.

#include <algorithm>
#include <cmath>
#include <string>
#include <variant>

#include <gtest/gtest.h>

#include "io/interface_test/interface_test_scene.hpp"
#include "io/scene/scene_error.hpp"
#include "io/scene/scene_toml.hpp"
#include "tests/io/scene_test_support.hpp"

namespace ifsim::io {
namespace {

using test::write_scene;

// The contract's example (scene-format.md), verbatim apart from comments.
const std::string contract_example = R"(kind = "interface-test"

[interface]
formulation = "novel"
model = "hypoplasticity"
parameters = "l4c"
roughness = 0.9
shear_band_thickness = 0.003
friction_coefficient = 0.25
tangential_stiffness = 6000.0
subincrement = "fixed"
max_subincrement = 5.0e-6
tolerance = 0.002
jacobian = "perturbation"
perturbation = 1.49e-8
void_ratio = 0.81
intergranular_strain = [0.0, 0.0, 0.0, 7.0710678e-5, 0.0, 0.0]

[sample]
model = "hypoplasticity"
parameters = "l4c"
height = 0.02
void_ratio = 0.81
stress = [-100.0, -50.0, -50.0, 0.0, 0.0, 0.0]
intergranular_strain = [0.0, 0.0, 0.0, 7.0710678e-5, 0.0, 0.0]

[normal]
control = "constant-stress"
stiffness = 400.0
stiffness_unit = "kPa/mm"

[[stage]]
steps = 1000
du_t1 = 0.006
du_t2 = 0.0
)";

// The smallest valid scene: everything else takes its default.
const std::string minimal = R"(kind = "interface-test"
[interface]
[sample]
stress = [-100.0, -50.0, -60.0, 0.0, 0.0, 0.0]
void_ratio = 0.8
[[stage]]
steps = 10
du_t1 = 0.001
)";

InterfaceTestScene parse_text(const std::string& text) {
    const std::string file = write_scene(text);
    return read_interface_test_scene(load_scene_table(file), file);
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

// Inserts `lines` right after the line `[table]`.
std::string with_in(const std::string& text, const std::string& table, const std::string& lines) {
    return replaced(text, "[" + table + "]\n", "[" + table + "]\n" + lines + "\n");
}

// Parsing must fail with a SceneError for exactly this key whose message names the file and
// the key and contains `expected`.
void expect_error(const std::string& text, const std::string& key, const std::string& expected) {
    const std::string file = write_scene(text);
    try {
        read_interface_test_scene(load_scene_table(file), file);
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

const HypoplasticityParams& hypo(const MaterialChoice& m) {
    return std::get<HypoplasticityParams>(m);
}

TEST(InterfaceScene, ContractExampleIsReadWithItsValues) {
    // The example lists the Coulomb keys and a CNS stiffness next to CNL for illustration;
    // as a scene they belong to another formulation and control, so they are taken out here.
    std::string text = replaced(contract_example, "friction_coefficient = 0.25\n", "");
    text = replaced(text, "tangential_stiffness = 6000.0\n", "");
    text = replaced(text, "control = \"constant-stress\"", "control = \"constant-stiffness\"");
    const InterfaceTestScene s = parse_text(text);
    EXPECT_EQ(s.spec.contact.interface.formulation, InterfaceFormulation::novel);
    EXPECT_FALSE(s.coulomb());
    EXPECT_EQ(s.interface_material.model, "hypoplasticity");
    EXPECT_EQ(s.interface_material.parameters, "l4c");
    EXPECT_DOUBLE_EQ(hypo(s.spec.interface_material).roughness, 0.9);
    EXPECT_DOUBLE_EQ(hypo(s.spec.interface_material).h_s, 4.5e6); // L4C, Table 1
    const InterfaceSettings& is = s.spec.contact.interface;
    EXPECT_EQ(is.formulation, InterfaceFormulation::novel);
    EXPECT_EQ(is.ndim, 3);
    EXPECT_DOUBLE_EQ(is.shear_band_thickness, 0.003);
    EXPECT_FALSE(is.adaptive);
    EXPECT_DOUBLE_EQ(is.max_subincrement, 5.0e-6);
    EXPECT_DOUBLE_EQ(is.tolerance, 0.002);
    EXPECT_EQ(s.spec.contact.jacobian, ContactJacobian::perturbation);
    EXPECT_DOUBLE_EQ(s.spec.contact.perturbation, 1.49e-8);
    ASSERT_EQ(s.spec.interface_state.size(), static_cast<std::size_t>(Hypoplasticity::n_state));
    EXPECT_DOUBLE_EQ(s.spec.interface_state[6], 0.81);
    EXPECT_DOUBLE_EQ(s.spec.interface_state[7 + 3], 7.0710678e-5);
    EXPECT_EQ(s.sample_material.model, "hypoplasticity");
    EXPECT_DOUBLE_EQ(hypo(s.spec.sample_material).roughness, 1.0); // the sample is continuum
    EXPECT_DOUBLE_EQ(s.spec.height, 0.02);
    ASSERT_EQ(s.spec.sample_state.size(), static_cast<std::size_t>(Hypoplasticity::n_state));
    EXPECT_DOUBLE_EQ(s.spec.sample_state[0], -100.0);
    EXPECT_DOUBLE_EQ(s.spec.sample_state[6], 0.81);
    EXPECT_DOUBLE_EQ(s.spec.sample_state[7 + 3], 7.0710678e-5);
    EXPECT_DOUBLE_EQ(s.initial_normal_stress(), -100.0);
    EXPECT_EQ(s.spec.control, NormalControl::constant_stiffness);
    EXPECT_DOUBLE_EQ(s.stiffness_given, 400.0);
    EXPECT_DOUBLE_EQ(s.spec.normal_stiffness, 4.0e5); // kPa/mm -> kPa/m
    ASSERT_EQ(s.spec.stages.size(), 1u);
    EXPECT_EQ(s.spec.stages[0].steps, 1000);
    EXPECT_DOUBLE_EQ(s.spec.stages[0].du_t1, 0.006);
    EXPECT_DOUBLE_EQ(s.spec.stages[0].du_t2, 0.0);
    EXPECT_EQ(s.total_steps(), 1000);
}

TEST(InterfaceScene, LeftOutKeysTakeTheContractDefaults) {
    const InterfaceTestScene s = parse_text(minimal);
    EXPECT_EQ(s.spec.contact.interface.formulation, InterfaceFormulation::novel);
    EXPECT_EQ(s.interface_material.model, "hypoplasticity");
    EXPECT_EQ(s.interface_material.parameters, "l4c");
    EXPECT_DOUBLE_EQ(hypo(s.spec.interface_material).roughness, 0.9);
    const InterfaceSettings& is = s.spec.contact.interface;
    EXPECT_DOUBLE_EQ(is.shear_band_thickness, 0.003);
    EXPECT_EQ(s.subincrement, "fixed");
    EXPECT_FALSE(is.adaptive);
    EXPECT_DOUBLE_EQ(is.max_subincrement, 5.0e-6);
    EXPECT_DOUBLE_EQ(is.tolerance, 0.002);
    EXPECT_DOUBLE_EQ(is.adaptive_tolerance, 0.002);
    EXPECT_EQ(s.jacobian, "perturbation");
    EXPECT_DOUBLE_EQ(s.spec.contact.perturbation, std::sqrt(2.220446049250313e-16));
    // Interface void ratio: the sample's; intergranular strain: zero.
    EXPECT_DOUBLE_EQ(s.spec.interface_state[6], 0.8);
    for (int k = 7; k < 13; ++k) {
        EXPECT_EQ(s.spec.interface_state[k], 0.0);
        EXPECT_EQ(s.spec.sample_state[k], 0.0);
    }
    EXPECT_EQ(s.sample_material.model, "hypoplasticity");
    EXPECT_EQ(s.sample_material.parameters, "l4c");
    EXPECT_DOUBLE_EQ(s.spec.height, 0.02);
    EXPECT_EQ(s.normal_control, "constant-stress");
    EXPECT_EQ(s.spec.control, NormalControl::constant_stress);
    EXPECT_DOUBLE_EQ(s.spec.stages[0].du_t2, 0.0);
    // No [integration]: the engine's defaults.
    const InterfaceTestSpec defaults;
    EXPECT_DOUBLE_EQ(s.spec.newton_tolerance, defaults.newton_tolerance);
    EXPECT_EQ(s.spec.max_newton_iterations, defaults.max_newton_iterations);

    const InterfaceTestScene stutz =
        parse_text(with_in(minimal, "interface", "formulation = \"stutz\""));
    EXPECT_EQ(stutz.stutz_initial_stress, "continuum");
    const InterfaceTestScene coulomb =
        parse_text(with_in(minimal, "interface", "formulation = \"coulomb\""));
    EXPECT_TRUE(coulomb.coulomb());
    EXPECT_DOUBLE_EQ(coulomb.spec.coulomb.friction_coefficient, 0.25);
    EXPECT_DOUBLE_EQ(coulomb.spec.coulomb.tangential_stiffness, 6000.0);
    const InterfaceTestScene cns =
        parse_text(minimal + "[normal]\ncontrol = \"constant-stiffness\"\nstiffness = 250.0\n");
    EXPECT_EQ(cns.stiffness_unit, "kPa/m");
    EXPECT_DOUBLE_EQ(cns.spec.normal_stiffness, 250.0);
}

TEST(InterfaceScene, InitialInterfaceStressFollowsTheFormulation) {
    // Distinct in-plane stresses and an initial shear stress tell the rules apart.
    const std::string base = replaced(minimal, "[-100.0, -50.0, -60.0, 0.0, 0.0, 0.0]",
                                      "[-100.0, -50.0, -60.0, 8.0, -3.0, 2.0]");
    struct Case {
        std::string lines;
        double s[6];
    };
    const Case cases[] = {
        {"formulation = \"novel\"", {-100.0, -50.0, -60.0, 8.0, -3.0, 0.0}},
        {"formulation = \"stutz\"", {-100.0, -50.0, -60.0, 8.0, -3.0, 0.0}},
        {"formulation = \"stutz\"\nstutz_initial_stress = \"continuum\"",
         {-100.0, -50.0, -60.0, 8.0, -3.0, 0.0}},
        {"formulation = \"stutz\"\nstutz_initial_stress = \"normal-contact\"",
         {-100.0, -100.0, -100.0, 8.0, -3.0, 0.0}},
    };
    for (const Case& c : cases) {
        const InterfaceTestScene s = parse_text(with_in(base, "interface", c.lines));
        for (int k = 0; k < 6; ++k) {
            EXPECT_EQ(s.spec.interface_state[k], c.s[k]) << c.lines << " component " << k;
        }
        EXPECT_EQ(s.spec.sample_state[5], 2.0); // the sample keeps its own s23
    }
}

TEST(InterfaceScene, EveryOptionalKeyIsRead) {
    const InterfaceTestScene s = parse_text(with_in(minimal + R"([integration]
tolerance = 1e-4
min_pressure = 0.5
max_substeps = 5000
newton_tolerance = 1e-6
max_newton_iterations = 12
interface_newton_jacobian = "perturbation"
interface_max_newton_iterations = 7
polish_iterations = 0
adaptive_tolerance = 1e-3
)",
                                                    "interface", R"(formulation = "stutz"
stutz_initial_stress = "normal-contact"
roughness = 0.5
shear_band_thickness = 0.006
subincrement = "adaptive"
max_subincrement = 1e-5
tolerance = 0.01
jacobian = "full-perturbation"
perturbation = 1e-7
void_ratio = 0.85
intergranular_strain = [0.0, 0.0, 0.0, -3e-5, 0.0, 0.0]
model = "hypoplasticity"
parameters = "karlsruhe-sand")"));
    const InterfaceSettings& is = s.spec.contact.interface;
    EXPECT_EQ(is.formulation, InterfaceFormulation::stutz);
    EXPECT_DOUBLE_EQ(hypo(s.spec.interface_material).roughness, 0.5);
    EXPECT_DOUBLE_EQ(hypo(s.spec.interface_material).h_s, 19.0e6); // Karlsruhe sand, Table 3
    EXPECT_DOUBLE_EQ(is.shear_band_thickness, 0.006);
    EXPECT_TRUE(is.adaptive);
    EXPECT_DOUBLE_EQ(is.max_subincrement, 1e-5);
    EXPECT_DOUBLE_EQ(is.tolerance, 0.01);
    EXPECT_DOUBLE_EQ(is.adaptive_tolerance, 1e-3);
    EXPECT_EQ(s.spec.contact.jacobian, ContactJacobian::full_perturbation);
    EXPECT_DOUBLE_EQ(s.spec.contact.perturbation, 1e-7);
    EXPECT_DOUBLE_EQ(s.spec.interface_state[6], 0.85);
    EXPECT_DOUBLE_EQ(s.spec.interface_state[7 + 3], -3e-5);
    EXPECT_EQ(is.newton_jacobian, NewtonJacobian::perturbation);
    EXPECT_EQ(is.max_newton_iterations, 7);
    EXPECT_EQ(is.polish_iterations, 0);
    EXPECT_DOUBLE_EQ(is.model.tolerance, 1e-4);
    EXPECT_DOUBLE_EQ(is.model.min_pressure, 0.5);
    EXPECT_EQ(is.model.max_substeps, 5000);
    EXPECT_DOUBLE_EQ(s.spec.sample_update.settings.tolerance, 1e-4);
    EXPECT_DOUBLE_EQ(s.spec.newton_tolerance, 1e-6);
    EXPECT_EQ(s.spec.max_newton_iterations, 12);

    const InterfaceTestScene a =
        parse_text(with_in(minimal, "interface", "jacobian = \"analytical\""));
    EXPECT_EQ(a.spec.contact.jacobian, ContactJacobian::analytical);

    const InterfaceTestScene c = parse_text(with_in(
        minimal, "interface",
        "formulation = \"coulomb\"\nfriction_coefficient = 0.4\ntangential_stiffness = 2e4"));
    EXPECT_EQ(c.spec.contact.interface.formulation, InterfaceFormulation::coulomb);
    EXPECT_DOUBLE_EQ(c.spec.coulomb.friction_coefficient, 0.4);
    EXPECT_DOUBLE_EQ(c.spec.coulomb.tangential_stiffness, 2e4);

    const InterfaceTestScene cns =
        parse_text(minimal + "[normal]\ncontrol = \"constant-stiffness\"\nstiffness = "
                             "2e5\nstiffness_unit = \"kPa/m\"\n");
    EXPECT_DOUBLE_EQ(cns.spec.normal_stiffness, 2e5);

    const InterfaceTestScene d = parse_text(replaced(minimal, "du_t1 = 0.001", "du_t2 = -0.002"));
    EXPECT_DOUBLE_EQ(d.spec.stages[0].du_t1, 0.0);
    EXPECT_DOUBLE_EQ(d.spec.stages[0].du_t2, -0.002);
}

TEST(InterfaceScene, SanisandInterfaceStartsOnTheConeAxisOfItsStress) {
    const InterfaceTestScene s =
        parse_text(with_in(minimal, "interface",
                           "model = \"sanisand\"\nformulation = \"stutz\"\n"
                           "stutz_initial_stress = \"normal-contact\""));
    EXPECT_EQ(s.interface_material.parameters, "karlsruhe-sand");
    ASSERT_EQ(s.spec.interface_state.size(), 25u);
    for (int k = 7; k < 25; ++k) { // isotropic interface stress: alpha = z = alpha_in = 0
        EXPECT_NEAR(s.spec.interface_state[k], 0.0, 1e-15) << k;
    }
    const InterfaceTestScene t =
        parse_text(with_in(minimal, "interface",
                           "model = \"sanisand\"\nback_stress = [0.43, -0.29, -0.14, 0.0, 0.0, "
                           "0.0]\nfabric = [1.0, -0.5, -0.5, 0.0, 0.0, 0.0]"));
    EXPECT_DOUBLE_EQ(t.spec.interface_state[7],
                     0.43); // r = dev(s)/(tr s / 3) = [0.429, -0.286, -0.143]
    EXPECT_DOUBLE_EQ(t.spec.interface_state[13], 1.0);
}

TEST(InterfaceScene, OverridesReachInterfaceKeys) {
    const std::string file = write_scene(minimal);
    toml::table table = load_scene_table(file);
    for (const char* set : {"interface.roughness=1.0", "interface.formulation=stutz",
                            "interface.stutz_initial_stress=normal-contact", "sample.height=0.05",
                            "normal.control=constant-stiffness", "normal.stiffness=400",
                            "normal.stiffness_unit=kPa/mm", "stage.1.du_t1=-0.002",
                            "integration.newton_tolerance=1e-5"}) {
        apply_override(table, set, file);
    }
    const InterfaceTestScene s = read_interface_test_scene(table, file);
    EXPECT_DOUBLE_EQ(hypo(s.spec.interface_material).roughness, 1.0);
    EXPECT_EQ(s.spec.contact.interface.formulation, InterfaceFormulation::stutz);
    EXPECT_EQ(s.spec.interface_state[1], -100.0);
    EXPECT_DOUBLE_EQ(s.spec.height, 0.05);
    EXPECT_DOUBLE_EQ(s.spec.normal_stiffness, 4.0e5);
    EXPECT_DOUBLE_EQ(s.spec.stages[0].du_t1, -0.002);
    EXPECT_DOUBLE_EQ(s.spec.newton_tolerance, 1e-5);

    toml::table bad = load_scene_table(file);
    apply_override(bad, "interface.rougness=0.5", file);
    try {
        read_interface_test_scene(bad, file);
        FAIL() << "misspelt key accepted";
    } catch (const SceneError& e) {
        EXPECT_EQ(e.key(), "interface.rougness");
    }
}

// The stagnation acceptance is off unless named (equal to the step tolerance), and never below
// the step tolerance.
TEST(InterfaceScene, StagnationToleranceIsOffUnlessNamedAndNeverBelowTheStepTolerance) {
    EXPECT_DOUBLE_EQ(parse_text(minimal).spec.stagnation_tolerance, 1e-4);
    const InterfaceTestScene tight =
        parse_text(minimal + "[integration]\nnewton_tolerance = 1e-8\n");
    EXPECT_DOUBLE_EQ(tight.spec.stagnation_tolerance, 1e-8);
    const InterfaceTestScene set = parse_text(
        minimal + "[integration]\nnewton_tolerance = 1e-6\nstagnation_tolerance = 1e-4\n");
    EXPECT_DOUBLE_EQ(set.spec.newton_tolerance, 1e-6);
    EXPECT_DOUBLE_EQ(set.spec.stagnation_tolerance, 1e-4);
    expect_error(minimal + "[integration]\nstagnation_tolerance = 1e-5\n",
                 "integration.stagnation_tolerance", "expected at least newton_tolerance (0.0001)");
}

TEST(InterfaceScene, OutOfRangeValuesNameTheirKey) {
    const std::string cns = minimal + "[normal]\ncontrol = \"constant-stiffness\"\n";
    const std::string coulomb = with_in(minimal, "interface", "formulation = \"coulomb\"");
    expect_error(with_in(minimal, "sample", "height = 0.0"), "sample.height",
                 "expected a number > 0");
    expect_error(with_in(minimal, "sample", "height = -0.02"), "sample.height", "> 0");
    expect_error(with_in(minimal, "interface", "shear_band_thickness = 0"),
                 "interface.shear_band_thickness", "> 0");
    expect_error(with_in(minimal, "interface", "tolerance = 1.0"), "interface.tolerance",
                 "in (0, 1)");
    expect_error(with_in(minimal, "interface", "tolerance = 0.0"), "interface.tolerance",
                 "in (0, 1)");
    expect_error(with_in(minimal, "interface", "max_subincrement = 0.0"),
                 "interface.max_subincrement", "> 0");
    expect_error(with_in(minimal, "interface", "perturbation = -1e-8"), "interface.perturbation",
                 "in (0, 1)");
    expect_error(with_in(minimal, "interface", "roughness = 0.0"), "interface.roughness",
                 "in (0, 1]");
    expect_error(with_in(minimal, "interface", "roughness = 1.1"), "interface.roughness",
                 "in (0, 1]");
    expect_error(with_in(minimal, "interface", "void_ratio = 2.0"), "interface.void_ratio",
                 "between e_d");
    expect_error(with_in(minimal, "interface", "intergranular_strain = [0, 0, 0, 1e-3, 0, 0]"),
                 "interface.intergranular_strain", "|h| <= R");
    expect_error(with_in(coulomb, "interface", "friction_coefficient = -0.1"),
                 "interface.friction_coefficient", ">= 0");
    expect_error(with_in(coulomb, "interface", "tangential_stiffness = 0"),
                 "interface.tangential_stiffness", "> 0");
    expect_error(cns + "stiffness = -1.0\n", "normal.stiffness", ">= 0");
    expect_error(cns, "normal.stiffness", "missing");
    expect_error(replaced(minimal, "steps = 10", "steps = 0"), "stage.1.steps", "from 1");
    expect_error(replaced(minimal, "[-100.0,", "[0.0,"), "sample.stress", "t_N0");
    expect_error(replaced(minimal, "[-100.0,", "[20.0,"), "sample.stress", "s11 < 0");
    expect_error(replaced(minimal, "void_ratio = 0.8", "void_ratio = -0.8"), "sample.void_ratio",
                 "> 0");
}

TEST(InterfaceScene, KeysOfAnotherFormulationOrModelAreErrors) {
    const std::string coulomb = with_in(minimal, "interface", "formulation = \"coulomb\"");
    expect_error(with_in(minimal, "interface", "friction_coefficient = 0.3"),
                 "interface.friction_coefficient", "applies to formulation \"coulomb\" only");
    expect_error(with_in(minimal, "interface", "tangential_stiffness = 6000.0"),
                 "interface.tangential_stiffness", "\"coulomb\" only");
    expect_error(with_in(minimal, "interface", "stutz_initial_stress = \"continuum\""),
                 "interface.stutz_initial_stress", "applies to formulation \"stutz\" only");
    for (const char* line :
         {"roughness = 0.9", "model = \"hypoplasticity\"", "parameters = \"l4c\"",
          "shear_band_thickness = 0.003", "subincrement = \"fixed\"", "jacobian = \"perturbation\"",
          "void_ratio = 0.8", "stutz_initial_stress = \"continuum\""}) {
        const std::string key = std::string(line).substr(0, std::string(line).find(' '));
        expect_error(with_in(coulomb, "interface", line), "interface." + key,
                     "applies to formulations \"novel\" and \"stutz\" only");
    }
    // the same wording as a boundary-value pair's (algorithm1_key_with_coulomb)
    expect_error(coulomb + "[integration]\npolish_iterations = 2\n",
                 "integration.polish_iterations",
                 "tunes Algorithm 1 of the continuum formulations \"novel\" and \"stutz\"; "
                 "expected no such key for formulation \"coulomb\"");
    expect_error(with_in(minimal, "interface", "back_stress = [0.1, -0.05, -0.05, 0, 0, 0]"),
                 "interface.back_stress", "applies to sanisand only");
    expect_error(with_in(minimal, "interface",
                         "model = \"sanisand\"\nintergranular_strain = [0, 0, 0, 0, 0, 0]"),
                 "interface.intergranular_strain", "applies to hypoplasticity only");
    expect_error(with_in(minimal, "sample", "fabric = [0, 0, 0, 0, 0, 0]"), "sample.fabric",
                 "applies to sanisand only");
    expect_error(minimal + "[normal]\nstiffness = 400.0\n", "normal.stiffness",
                 "applies to control = \"constant-stiffness\" only");
    expect_error(minimal + "[normal]\nstiffness_unit = \"kPa/mm\"\n", "normal.stiffness_unit",
                 "\"constant-stiffness\" only");
    // Coulomb: the initial shear stress must lie inside the friction cone.
    expect_error(replaced(coulomb, "[-100.0, -50.0, -60.0, 0.0,", "[-100.0, -50.0, -60.0, 30.0,"),
                 "interface.friction_coefficient", "exceeds the friction limit");
}

TEST(InterfaceScene, UnknownKeysTypesAndChoicesAreErrors) {
    expect_error(with_in(minimal, "interface", "formulation = \"mohr\""), "interface.formulation",
                 "one of \"novel\" | \"stutz\" | \"coulomb\"");
    expect_error(with_in(minimal, "interface", "model = \"linear-elastic\""), "interface.model",
                 "\"hypoplasticity\" | \"sanisand\"");
    expect_error(with_in(minimal, "interface", "jacobian = \"exact\""), "interface.jacobian",
                 "\"perturbation\" | \"central\" | \"full-perturbation\" | \"analytical\"");
    expect_error(with_in(minimal, "interface", "subincrement = \"variable\""),
                 "interface.subincrement", "\"fixed\" | \"adaptive\"");
    expect_error(
        with_in(minimal, "interface", "stutz_initial_stress = \"abaqus\"\nformulation = \"stutz\""),
        "interface.stutz_initial_stress", "\"continuum\" | \"normal-contact\"");
    expect_error(minimal + "[normal]\ncontrol = \"constant-stiffness\"\nstiffness = 4.0\n"
                           "stiffness_unit = \"kN/m\"\n",
                 "normal.stiffness_unit", "\"kPa/m\" | \"kPa/mm\"");
    expect_error(minimal + "[normal]\ncontrol = \"cnl\"\n", "normal.control",
                 "\"constant-stress\" | \"constant-stiffness\"");
    expect_error(with_in(minimal, "interface", "parameters = \"ottawa\""), "interface.parameters",
                 "no built-in hypoplasticity parameter set");
    expect_error(with_in(minimal, "interface", "shear_band = 0.003"), "interface.shear_band",
                 "unknown key");
    expect_error(with_in(minimal, "sample", "roughness = 0.9"), "sample.roughness", "unknown key");
    expect_error(minimal + "[normal]\nk = 1\n", "normal.k", "unknown key");
    expect_error(replaced(minimal, "du_t1 = 0.001", "du_n = 0.001"), "stage.1.du_n", "unknown key");
    expect_error(minimal + "[integration]\ntangent = \"rate\"\n", "integration.tangent",
                 "unknown key");
    expect_error(minimal + "[material]\nmodel = \"sanisand\"\n", "material", "unknown key");
    expect_error(with_in(minimal, "interface", "shear_band_thickness = \"3 mm\""),
                 "interface.shear_band_thickness", "got a string");
    expect_error(replaced(minimal, "[interface]\n", ""), "interface", "missing");
    expect_error(replaced(minimal, "[[stage]]\nsteps = 10\ndu_t1 = 0.001\n", ""), "stage",
                 "missing");
    expect_error(replaced(minimal, "stress = [-100.0, -50.0, -60.0, 0.0, 0.0, 0.0]\n", ""),
                 "sample.stress", "missing");
}

TEST(InterfaceScene, ShippedScenesAreValid) {
    for (const char* name :
         {"simple-shear-cnl", "simple-shear-cnl-stutz", "simple-shear-cnl-coulomb",
          "cyclic-cns-novel", "cyclic-cns-stutz", "appendix-c-novel", "appendix-c-stutz-continuum",
          "appendix-c-stutz-normal-contact"}) {
        const std::string file = std::string("scenes/") + name + ".toml";
        const InterfaceTestScene s = read_interface_test_scene(load_scene_table(file), file);
        EXPECT_EQ(s.sample_material.parameters, "l4c") << name;
        EXPECT_DOUBLE_EQ(s.spec.height, 0.02) << name;
        EXPECT_DOUBLE_EQ(s.spec.sample_state[6], 0.81) << name;
        if (!s.coulomb()) {
            EXPECT_EQ(s.interface_material.parameters, "l4c") << name;
            EXPECT_DOUBLE_EQ(s.spec.interface_state[6], 0.81) << name;
            EXPECT_DOUBLE_EQ(s.spec.interface_state[7 + 3], 7.0710678e-5) << name;
        }
    }
    // Cyclic CNS: t_N0 = 300 kPa, K = 400 kPa/mm, 11 cycles of +-0.75 mm ending at 0.
    const std::string file = "scenes/cyclic-cns-novel.toml";
    const InterfaceTestScene c = read_interface_test_scene(load_scene_table(file), file);
    EXPECT_DOUBLE_EQ(c.initial_normal_stress(), -300.0);
    EXPECT_DOUBLE_EQ(c.spec.normal_stiffness, 4.0e5);
    ASSERT_EQ(c.spec.stages.size(), 23u);
    double u = 0.0, top = 0.0, bottom = 0.0;
    for (const auto& st : c.spec.stages) {
        u += st.du_t1;
        top = std::max(top, u);
        bottom = std::min(bottom, u);
    }
    EXPECT_NEAR(u, 0.0, 1e-15);
    EXPECT_NEAR(top, 0.00075, 1e-15);
    EXPECT_NEAR(bottom, -0.00075, 1e-15);
}

} // namespace
} // namespace ifsim::io
