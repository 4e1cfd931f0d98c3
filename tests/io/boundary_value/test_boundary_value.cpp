// Boundary-value scenes (finite elements): the shipped scenes are read, bad input is a
// SceneError naming the file and the key, a short run through the command line writes the
// history columns and the summary's phases, a run without contact, gravity and K0 spends
// nothing on them, and the FE shear box agrees with the point-level interface test.

#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "engine/interface_test_driver.hpp"
#include "io/boundary_value/boundary_value_scene.hpp"
#include "io/cli/cli.hpp"
#include "io/interface_test/interface_test_scene.hpp"
#include "io/scene/scene_error.hpp"
#include "io/scene/scene_toml.hpp"
#include "tests/io/boundary_value_test_support.hpp"
#include "tests/io/scene_test_support.hpp"

namespace ifsim::io {
namespace {

namespace fs = std::filesystem;

const char* const cnl_2d = "scenes/fe-simple-shear-cnl-2d.toml";

int run(std::vector<std::string> args) {
    return test::run_cli_captured(std::move(args)).code;
}

using test::History;
using test::read_history;
using test::summary;

TEST(BoundaryValueScene, ShippedScenesAreRead) {
    for (const char* name :
         {"fe-simple-shear-cnl-2d", "fe-simple-shear-cnl-3d", "fe-simple-shear-cns-2d",
          "fe-simple-shear-stutz-2d", "fe-simple-shear-coulomb-2d", "fe-appendix-c-continuum-2d",
          "fe-sliding-block-2d", "fe-contact-patch-2d", "fe-rough-and-smooth-2d"}) {
        const std::string file = std::string("scenes/") + name + ".toml";
        const BoundaryValueScene s = test::parse_boundary_value(file);
        EXPECT_FALSE(s.stages.empty()) << name;
        EXPECT_GT(s.mesh.n_elements(), 0) << name;
        EXPECT_TRUE(s.mesh.node_sets.contains(s.output.plate)) << name;
    }
    const BoundaryValueScene s = test::parse_boundary_value(cnl_2d);
    ASSERT_EQ(s.contacts.size(), 1u);
    EXPECT_EQ(s.contacts[0].pair.name, "interface");
    EXPECT_EQ(s.contacts[0].formulation.name(), "novel");
    EXPECT_DOUBLE_EQ(s.contacts[0].formulation.material.roughness, 0.9);
    // Sets are "<body>.<set>"; each body's elements are the element set "<body>".
    EXPECT_EQ(s.mesh.element_set("soil").size(), 1u);
    EXPECT_EQ(s.mesh.node_set("plate.all").size(), 4u);
    // The interface state: stress from the local continuum stress, the keys' void ratio and
    // intergranular strain in local axes.
    const std::vector<double> y = s.contacts[0].pair.initial_state({-100.0, -50.0, -50.0, 0, 0, 0});
    EXPECT_DOUBLE_EQ(y[0], -100.0);
    EXPECT_DOUBLE_EQ(y[6], 0.81);
    EXPECT_DOUBLE_EQ(y[7 + 3], 7.0710678e-5);
    // CNS: the spring's total stiffness is K times the top's area (0.1 m per m in 2D).
    const BoundaryValueScene cns = test::parse_boundary_value("scenes/fe-simple-shear-cns-2d.toml");
    ASSERT_EQ(cns.stages[1].springs.size(), 1u);
    EXPECT_NEAR(cns.stages[1].springs[0].total_stiffness, 400.0e3 * 0.1, 1e-6);
}

// The §6 large-scale test (scenes/large-shear-coarse.toml and scenes/large-shear/,
// docs/large-scale-test.md): the Gmsh meshes
// are read with their regions and face sets, four contact pairs each, the rough pair's frame
// along the wall's downward motion; the fine mesh has at least 20 k DOFs.
TEST(BoundaryValueScene, LargeShearScenesAreRead) {
    for (const char* name :
         {"large-shear-coarse", "large-shear-novel-hypo", "large-shear-novel-sanisand",
          "large-shear-stutz-hypo", "large-shear-coulomb"}) {
        // The coarse twin sits with the main job's scenes, the four fine runs in their folder.
        const std::string file = std::string(name) == "large-shear-coarse"
                                     ? std::string("scenes/large-shear-coarse.toml")
                                     : std::string("scenes/large-shear/") + name + ".toml";
        const BoundaryValueScene s = test::parse_boundary_value(file);
        EXPECT_EQ(s.mesh.dim(), 3) << name;
        EXPECT_EQ(s.contacts.size(), 4u) << name;
        EXPECT_EQ(s.settings.kinematics, fem::Kinematics::updated_lagrangian) << name;
        EXPECT_EQ(s.stages.size(), 8u) << name;
        const auto& rough = s.contacts.at(s.output.contact).pair;
        EXPECT_EQ(rough.name, "rough") << name;
        EXPECT_EQ(rough.shear_direction, (std::array<double, 3>{0.0, 0.0, -1.0})) << name;
        if (std::string(name) != "large-shear-coarse") {
            EXPECT_GE(3 * s.mesh.n_nodes(), 20000) << name;
        }
    }
}

TEST(BoundaryValueScene, SetReachesNestedKeys) {
    const BoundaryValueScene s = test::parse_boundary_value(
        cnl_2d, {"stage.2.displacement.1.change=0.001", "interface.roughness=0.5",
                 "material.sand.void_ratio=0.75", "body.1.elements=[2, 1]",
                 "interface.open_threshold=0.1"});
    EXPECT_DOUBLE_EQ(s.stages[1].displacements[0].change, 0.001);
    EXPECT_DOUBLE_EQ(s.contacts.at(0).pair.options.interface.open_threshold, 0.1);
    EXPECT_DOUBLE_EQ(s.contacts.at(0).formulation.material.roughness, 0.5);
    EXPECT_DOUBLE_EQ(s.materials.at("soil").void_ratio, 0.75);
    EXPECT_EQ(s.mesh.element_set("soil").size(), 2u);
}

// adaptive_partition: held per increment by default, chosen anew with "iteration"; any other
// word is refused naming the key.
TEST(BoundaryValueScene, AdaptivePartitionKey) {
    EXPECT_TRUE(test::parse_boundary_value(cnl_2d).contacts.at(0).pair.hold_partition);
    EXPECT_FALSE(test::parse_boundary_value(cnl_2d, {"interface.adaptive_partition=\"iteration\""})
                     .contacts.at(0)
                     .pair.hold_partition);
    const std::string text = test::read_text(cnl_2d);
    test::expect_boundary_value_error(
        test::replaced(text, "roughness = 0.9", "roughness = 0.9\nadaptive_partition = \"step\""),
        "interface.adaptive_partition", "\"increment\" | \"iteration\"");
}

// model_integration: backward-Euler steps reach a Sanisand pair's model settings; a
// hypoplastic pair refuses them, naming the key.
TEST(BoundaryValueScene, ImplicitModelIntegrationOnlyForSanisand) {
    EXPECT_FALSE(test::parse_boundary_value(cnl_2d)
                     .contacts.at(0)
                     .pair.options.interface.model.backward_euler);
    const std::string text = test::read_text(cnl_2d);
    const std::string sanisand = test::replaced(
        test::replaced(text, "model = \"hypoplasticity\"\nparameters = \"l4c\"\nroughness = 0.9",
                       "model = \"sanisand\"\nparameters = \"karlsruhe-sand\"\nroughness = "
                       "0.9\nmodel_integration = \"implicit\""),
        "intergranular_strain = [0.0, 0.0, 0.0, 7.0710678e-5, 0.0, 0.0]", "");
    EXPECT_TRUE(test::parse_boundary_value(test::write_scene(sanisand))
                    .contacts.at(0)
                    .pair.options.interface.model.backward_euler);
    test::expect_boundary_value_error(
        test::replaced(text, "roughness = 0.9",
                       "roughness = 0.9\nmodel_integration = \"implicit\""),
        "interface.model_integration", "\"explicit\" with this interface model");
}

// polish_iterations (Algorithm 1's Newton corrections after its tolerance is met) reaches the
// pair's interface settings; the keys that tune Algorithm 1 are refused with Coulomb friction
// (they were read and ignored before), naming the key.
TEST(BoundaryValueScene, PolishIterationsKeyAndInnerSolveKeysRefusedWithCoulomb) {
    EXPECT_EQ(
        test::parse_boundary_value(cnl_2d).contacts.at(0).pair.options.interface.polish_iterations,
        1);
    EXPECT_EQ(test::parse_boundary_value(cnl_2d, {"interface.polish_iterations=3"})
                  .contacts.at(0)
                  .pair.options.interface.polish_iterations,
              3);
    const std::string text = test::read_text(cnl_2d);
    test::expect_boundary_value_error(
        test::replaced(text, "roughness = 0.9", "roughness = 0.9\npolish_iterations = 11"),
        "interface.polish_iterations", "10");
    const std::string coulomb = test::read_text("scenes/fe-simple-shear-coulomb-2d.toml");
    for (const char* key :
         {"model_tolerance = 1e-5", "model_integration = \"implicit\"", "polish_iterations = 2",
          "adaptive_partition = \"iteration\"", "defer_jacobian = true"}) {
        const std::string name = std::string(key).substr(0, std::string(key).find(' '));
        test::expect_boundary_value_error(
            test::replaced(coulomb, "formulation = \"coulomb\"",
                           std::string("formulation = \"coulomb\"\n") + key),
            "interface." + name,
            "tunes Algorithm 1 of the continuum formulations \"novel\" and \"stutz\"; expected no "
            "such key for formulation \"coulomb\"");
    }
}

// defer_jacobian (Eq. 37's lanes only for the tangent) reaches the pair; off by default.
TEST(BoundaryValueScene, DeferJacobianKey) {
    EXPECT_FALSE(test::parse_boundary_value(cnl_2d).contacts.at(0).pair.defer_jacobian);
    EXPECT_TRUE(test::parse_boundary_value(cnl_2d, {"interface.defer_jacobian=true"})
                    .contacts.at(0)
                    .pair.defer_jacobian);
    test::expect_boundary_value_error(test::replaced(test::read_text(cnl_2d), "roughness = 0.9",
                                                     "roughness = 0.9\ndefer_jacobian = \"yes\""),
                                      "interface.defer_jacobian", "true or false");
}

// newton_switch_jacobian (what a creeping rate-Jacobian lane switches to) reaches the pair:
// Broyden's updates by default, the perturbation Jacobian on request; another word is refused
// naming the key and its choices, and Coulomb friction refuses the key.
TEST(BoundaryValueScene, NewtonSwitchJacobianKey) {
    const auto interface_of = [](const BoundaryValueScene& s) {
        return s.contacts.at(0).pair.options.interface;
    };
    EXPECT_TRUE(interface_of(test::parse_boundary_value(cnl_2d)).newton_switch_broyden);
    const auto perturbation = interface_of(
        test::parse_boundary_value(cnl_2d, {"interface.newton_switch_ratio=0.5",
                                            "interface.newton_switch_jacobian=\"perturbation\""}));
    EXPECT_FALSE(perturbation.newton_switch_broyden);
    EXPECT_DOUBLE_EQ(perturbation.newton_switch_ratio, 0.5);
    test::expect_boundary_value_error(
        test::replaced(test::read_text(cnl_2d), "roughness = 0.9",
                       "roughness = 0.9\nnewton_switch_jacobian = \"secant\""),
        "interface.newton_switch_jacobian", "\"broyden\" | \"perturbation\"");
    test::expect_boundary_value_error(
        test::replaced(test::read_text("scenes/fe-simple-shear-coulomb-2d.toml"),
                       "formulation = \"coulomb\"",
                       "formulation = \"coulomb\"\nnewton_switch_jacobian = \"perturbation\""),
        "interface.newton_switch_jacobian", "expected no such key for formulation \"coulomb\"");
}

// newton_line_search: 0 (the paper's plain Newton) unless named; bounded, refused with
// Coulomb, naming the key.
TEST(BoundaryValueScene, NewtonLineSearchKey) {
    const auto interface_of = [](const BoundaryValueScene& s) {
        return s.contacts.at(0).pair.options.interface;
    };
    EXPECT_EQ(interface_of(test::parse_boundary_value(cnl_2d)).newton_line_search, 0);
    EXPECT_EQ(interface_of(test::parse_boundary_value(cnl_2d, {"interface.newton_line_search=4"}))
                  .newton_line_search,
              4);
    test::expect_boundary_value_error(test::replaced(test::read_text(cnl_2d), "roughness = 0.9",
                                                     "roughness = 0.9\nnewton_line_search = -1"),
                                      "interface.newton_line_search", "an integer from 0 to 60");
    test::expect_boundary_value_error(
        test::replaced(test::read_text("scenes/fe-simple-shear-coulomb-2d.toml"),
                       "formulation = \"coulomb\"",
                       "formulation = \"coulomb\"\nnewton_line_search = 4"),
        "interface.newton_line_search", "expected no such key for formulation \"coulomb\"");
}

// slip_viscosity (a viscous shear traction on a continuum interface, docs/fem.md): off by
// default, in every increment unless slip_viscosity_use = "retry"; negative values, a use
// without a viscosity and Coulomb pairs are refused naming the key.
TEST(BoundaryValueScene, SlipViscosityKeys) {
    const auto plain = test::parse_boundary_value(cnl_2d).contacts.at(0).pair;
    EXPECT_EQ(plain.slip_viscosity, 0.0);
    const auto kept =
        test::parse_boundary_value(cnl_2d, {"interface.slip_viscosity=500"}).contacts.at(0).pair;
    EXPECT_EQ(kept.slip_viscosity, 500.0);
    EXPECT_TRUE(kept.slip_viscosity_always);
    EXPECT_FALSE(test::parse_boundary_value(cnl_2d, {"interface.slip_viscosity=500",
                                                     "interface.slip_viscosity_use=\"retry\""})
                     .contacts.at(0)
                     .pair.slip_viscosity_always);
    const std::string text = test::read_text(cnl_2d);
    test::expect_boundary_value_error(
        test::replaced(text, "roughness = 0.9", "roughness = 0.9\nslip_viscosity = -1"),
        "interface.slip_viscosity", ">= 0");
    test::expect_boundary_value_error(
        test::replaced(text, "roughness = 0.9",
                       "roughness = 0.9\nslip_viscosity = 10\nslip_viscosity_use = \"once\""),
        "interface.slip_viscosity_use", "\"always\" | \"retry\"");
    test::expect_boundary_value_error(
        test::replaced(text, "roughness = 0.9", "roughness = 0.9\nslip_viscosity_use = \"retry\""),
        "interface.slip_viscosity_use", "a slip_viscosity beside it");
    // A scene's viscosity switched off from the command line keeps its use key.
    const std::string with_use = test::write_scene(
        test::replaced(text, "roughness = 0.9",
                       "roughness = 0.9\nslip_viscosity = 500\nslip_viscosity_use = \"always\""));
    EXPECT_EQ(test::parse_boundary_value(with_use, {"interface.slip_viscosity=0"})
                  .contacts.at(0)
                  .pair.slip_viscosity,
              0.0);
    const std::string coulomb = test::read_text("scenes/fe-simple-shear-coulomb-2d.toml");
    test::expect_boundary_value_error(
        test::replaced(coulomb, "formulation = \"coulomb\"",
                       "formulation = \"coulomb\"\nslip_viscosity = 10"),
        "interface.slip_viscosity", "expected no such key");
}

TEST(BoundaryValueScene, BadInputNamesFileAndKey) {
    const std::string text = test::read_text(cnl_2d);
    test::expect_boundary_value_error(
        test::replaced(text, "dimension = 2", "dimension = 2\ncolour = 1"), "mesh.colour",
        "unknown key");
    test::expect_boundary_value_error(test::replaced(text, "dimension = 2", "dimension = \"two\""),
                                      "mesh.dimension", "expected an integer");
    test::expect_boundary_value_error(test::replaced(text, "size = [0.1, 0.02]", "size = [0.1]"),
                                      "body.1.size", "array of 2");
    test::expect_boundary_value_error(test::replaced(text, "void_ratio = 0.81\nstress", "stress"),
                                      "material.sand.void_ratio", "missing");
    test::expect_boundary_value_error(
        test::replaced(text, "master = \"plate.top\"", "master = \"plate.up\""), "interface.master",
        "face set");
    test::expect_boundary_value_error(
        test::replaced(text, "roughness = 0.9", "friction_coefficient = 0.3"),
        "interface.friction_coefficient", "coulomb");
    test::expect_boundary_value_error(
        test::replaced(text, "material = \"steel\"", "material = \"iron\""), "body.2.material",
        "material");
    test::expect_boundary_value_error(
        test::replaced(text, "direction = \"x\", change", "direction = \"z\", change"),
        "stage.2.displacement.1.direction", "\"x\" | \"y\"");
    test::expect_boundary_value_error(test::replaced(text, "steps = 600", "steps = 0"),
                                      "stage.2.steps", "integer");
    test::expect_boundary_value_error(test::replaced(text, "soil_top = \"soil.top\"", ""),
                                      "output.soil_top", "missing");
    // Traction faces belong to runs without contact.
    test::expect_boundary_value_error(
        test::replaced(text, "soil_top = \"soil.top\"",
                       "soil_top = \"soil.top\"\ntraction_faces = \"soil.bottom\""),
        "output.traction_faces", "without [interface]");
    test::expect_boundary_value_error(
        test::replaced(text, "dimension = 2", "dimension = 2\nkinematics = \"large\""),
        "mesh.kinematics", "\"updated-lagrangian\"");
    // A state key checked at parse time with the soil's stress: |h| > R.
    test::expect_boundary_value_error(
        test::replaced(text, "intergranular_strain = [0.0, 0.0, 0.0, 7.0710678e-5, 0.0, 0.0]",
                       "intergranular_strain = [0.0, 0.0, 0.0, 7.0e-3, 0.0, 0.0]"),
        "interface.intergranular_strain", "R =");
    // Contradicting constraints of a stage.
    test::expect_boundary_value_error(
        test::replaced(text,
                       "{ nodes = \"soil.top\", direction = \"x\" } ]\nequal = [ { nodes "
                       "= \"soil.top\", direction = \"y\" }, { nodes = \"soil.bottom\", "
                       "direction = \"x\" },\n          { nodes = \"soil.bottom\", "
                       "direction = \"y\" } ]\npressure",
                       "{ nodes = \"soil.top\", direction = \"x\" } ]\nequal = [ { nodes = "
                       "\"soil.top\", direction = \"x\" } ]\npressure"),
        "stage.1", "contradict");
    // The first guess: one of three names, and not both the key and its older form.
    const std::string with_output = "[output]";
    test::expect_boundary_value_error(
        test::replaced(text, with_output, "[solver]\npredictor = \"linear\"\n\n[output]"),
        "solver.predictor", "\"tangent\"");
    test::expect_boundary_value_error(
        test::replaced(text, with_output,
                       "[solver]\npredictor = \"zero\"\nextrapolate = true\n\n[output]"),
        "solver.extrapolate", "not both");
    // The early cut of diverged Newton solves is switched by a boolean.
    test::expect_boundary_value_error(
        test::replaced(text, with_output, "[solver]\ndivergence_check = 1\n\n[output]"),
        "solver.divergence_check", "true or false");
    // Reused factorisations: a switch, a tolerance in (0, 1), a step budget, a cost >= 0.
    for (const auto& [line, key, expected] : std::vector<std::array<std::string, 3>>{
             {"reuse_factorisation = 1", "solver.reuse_factorisation", "true or false"},
             {"krylov_tolerance = 0.0", "solver.krylov_tolerance", "(0, 1)"},
             {"krylov_max_iterations = 0", "solver.krylov_max_iterations", "from 1 to 1000"},
             {"krylov_factorisation_cost = -1.0", "solver.krylov_factorisation_cost", ">= 0"},
             {"preconditioner_precision = \"half\"", "solver.preconditioner_precision",
              "\"double\""},
             {"early_gather_residual = 1.0", "solver.early_gather_residual", "[0, 1)"},
             {"early_gather_residual = -1e-5", "solver.early_gather_residual", "[0, 1)"}}) {
        test::expect_boundary_value_error(
            test::replaced(text, with_output, "[solver]\n" + line + "\n\n[output]"), key,
            expected.c_str());
    }
}

TEST(BoundaryValueRun, ShortRunWritesHistoryAndSummary) {
    const fs::path dir = test::fresh_dir("bv-run");
    ASSERT_EQ(run({"run", cnl_2d, "--out", dir.string(), "--set", "stage.2.steps=5", "--set",
                   "stage.2.displacement.1.change=0.00015"}),
              0);
    const History h = read_history(dir);
    const std::vector<std::string> first = {"increment", "stage", "time", "newton_iterations",
                                            "u_t1",      "u_t2",  "u_n",  "t_n",
                                            "t_t1",      "t_t2"};
    ASSERT_GE(h.names.size(), first.size());
    EXPECT_EQ(std::vector<std::string>(h.names.begin(), h.names.begin() + 10), first);
    for (const char* c :
         {"cuts", "closed_points", "s_p1", "s_p2", "eps_n", "band_thickness", "e_interface"}) {
        EXPECT_NE(std::find(h.names.begin(), h.names.end(), c), h.names.end()) << c;
    }
    ASSERT_EQ(h.rows.size(), 7u); // row 0, consolidation, 5 shear increments
    EXPECT_DOUBLE_EQ(h.number(0, "t_n"), -100.0);
    EXPECT_DOUBLE_EQ(h.number(0, "s_p1"), -50.0);
    EXPECT_NEAR(h.number(1, "t_n"), -100.0, 1e-6); // prestressed: starts in equilibrium
    EXPECT_NEAR(h.number(6, "u_t1"), 0.00015, 1e-12);
    EXPECT_DOUBLE_EQ(h.number(6, "time"), 2.0);
    EXPECT_GT(h.number(6, "t_t1"), 10.0);          // the plate drags the soil along +x
    EXPECT_NEAR(h.number(6, "t_n"), -100.0, 1e-3); // CNL

    const nlohmann::json s = summary(dir);
    EXPECT_EQ(s["kind"], "boundary-value");
    EXPECT_EQ(s["status"], "ok");
    for (const char* p :
         {"parse", "element", "assembly", "solve", "contact_search", "contact_gather",
          "contact_kernels", "contact_scatter", "gravity", "k0", "pressure", "output"}) {
        EXPECT_TRUE(s["timing"]["phases"].contains(p)) << p;
    }
    EXPECT_GT(s["timing"]["phases"]["contact_kernels"].get<double>(), 0.0);
    EXPECT_EQ(s["counters"]["increments"], 6);
    EXPECT_GT(s["counters"]["subincrements"].get<long>(), 0);
    EXPECT_GT(s["counters"]["contact_evaluations"].get<long>(), 0);
    EXPECT_TRUE(s["counters"].contains("divergence_cuts"));
    EXPECT_EQ(s["mesh"]["equations"], 3); // top y, bottom x, bottom y (ties)
    EXPECT_GE(s["iterations_per_increment"]["max"].get<int>(), 1);
}

// [mesh] kinematics reaches the solver and the summary; the same short shear with updated
// Lagrangian differs from small strain only by the small strains of the soil.
TEST(BoundaryValueRun, UpdatedLagrangianIsAnEffectTheSceneAsksFor) {
    const fs::path small = test::fresh_dir("bv-small-strain");
    const fs::path ul = test::fresh_dir("bv-updated-lagrangian");
    const std::vector<std::string> shear = {"--set", "stage.2.steps=5", "--set",
                                            "stage.2.displacement.1.change=0.00015"};
    std::vector<std::string> a = {"run", cnl_2d, "--out", small.string()};
    a.insert(a.end(), shear.begin(), shear.end());
    ASSERT_EQ(run(a), 0);
    std::vector<std::string> b = {"run",       cnl_2d,  "--out",
                                  ul.string(), "--set", "mesh.kinematics=\"updated-lagrangian\""};
    b.insert(b.end(), shear.begin(), shear.end());
    ASSERT_EQ(run(b), 0);
    EXPECT_EQ(summary(small)["effects"]["kinematics"], "small-strain");
    EXPECT_EQ(summary(ul)["effects"]["kinematics"], "updated-lagrangian");
    EXPECT_EQ(summary(ul)["mesh"]["kinematics"], "updated-lagrangian");
    // Small strain builds no geometry after the first; updated Lagrangian one per increment
    // after the first (the reference serves the first).
    EXPECT_EQ(summary(small)["counters"]["geometry_updates"], 0);
    EXPECT_EQ(summary(ul)["counters"]["geometry_updates"], 5);
    const History hs = read_history(small);
    const History hu = read_history(ul);
    const double ts = hs.number(6, "t_t1"), tu = hu.number(6, "t_t1");
    EXPECT_NE(ts, tu);
    EXPECT_NEAR(tu, ts, 1e-2 * std::abs(ts));
}

TEST(BoundaryValueRun, NoContactNoGravityNoK0CostsNothing) {
    const fs::path dir = test::fresh_dir("bv-nocontact");
    ASSERT_EQ(run({"run", "scenes/fe-appendix-c-continuum-2d.toml", "--out", dir.string(), "--set",
                   "stage.2.steps=5", "--set", "stage.2.displacement.1.change=0.0003"}),
              0);
    const nlohmann::json s = summary(dir);
    for (const char* p : {"contact_search", "contact_gather", "contact_kernels", "contact_scatter",
                          "gravity", "k0"}) {
        EXPECT_EQ(s["timing"]["phases"][p].get<double>(), 0.0) << p;
    }
    EXPECT_FALSE(s["counters"].contains("contact_evaluations"));
    EXPECT_EQ(s["counters"]["subincrements"], 0);
    EXPECT_EQ(s["counters"]["k0_points"], 0);
    EXPECT_EQ(s["counters"]["gravity_load_applications"], 0);
    const History h = read_history(dir);
    // Reactions on the bottom: the constant normal stress and a growing shear stress.
    EXPECT_NEAR(h.number(h.rows.size() - 1, "t_n"), -100.0, 1e-6);
    EXPECT_GT(h.number(h.rows.size() - 1, "t_t1"), 10.0);
    EXPECT_EQ(h.rows.back().at("closed_points"), "");
    EXPECT_EQ(h.rows.back().at("e_interface"), "");
}

// The FE shear box against the point-level interface test with the same parameters: t_t1 at
// the same plate displacement within a few percent (2D: the interface is in plane strain).
TEST(BoundaryValueRun, ShearBoxAgreesWithPointLevelInterfaceTest) {
    const fs::path dir = test::fresh_dir("bv-twin");
    ASSERT_EQ(run({"run", cnl_2d, "--out", dir.string(), "--set", "stage.2.steps=20", "--set",
                   "stage.2.displacement.1.change=0.0006"}),
              0);
    const History fe = read_history(dir);

    const std::string file = "scenes/simple-shear-cnl.toml";
    toml::table t = load_scene_table(file);
    apply_override(t, "stage.1.steps=20", file);
    apply_override(t, "stage.1.du_t1=0.0006", file);
    const InterfaceTestScene point = read_interface_test_scene(t, file);
    std::vector<InterfaceRow> rows;
    const InterfaceTestResult r =
        run_interface_test(point.spec, [&](const InterfaceRow& row) { rows.push_back(row); });
    ASSERT_TRUE(r.ok) << r.reason;
    ASSERT_EQ(rows.size(), 21u);
    ASSERT_EQ(fe.rows.size(), 22u);
    for (std::size_t k = 1; k < rows.size(); ++k) {
        const std::size_t f = k + 1; // FE: row 0 and the consolidation increment come first
        ASSERT_NEAR(fe.number(f, "u_t1"), rows[k].u_t1, 1e-12);
        EXPECT_NEAR(fe.number(f, "t_t1"), rows[k].t_t1, 0.05 * rows[k].t_t1) << "row " << k;
        EXPECT_NEAR(fe.number(f, "u_n"), rows[k].u_n, 0.1 * std::abs(rows[k].u_n) + 1e-7);
    }
}

} // namespace
} // namespace ifsim::io
