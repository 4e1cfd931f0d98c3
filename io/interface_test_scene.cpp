#include "io/interface_test_scene.hpp"

#include <cmath>
#include <string_view>

#include <fmt/format.h>

#include "io/element_initial_state.hpp"
#include "io/table_reader.hpp"

namespace ifsim::io {

namespace {

using Six = std::array<double, 6>;

// [interface] keys of the continuum formulations (novel, stutz) and of Coulomb friction.
constexpr std::string_view continuum_keys[] = {"model",
                                               "parameters",
                                               "roughness",
                                               "shear_band_thickness",
                                               "stutz_initial_stress",
                                               "subincrement",
                                               "max_subincrement",
                                               "tolerance",
                                               "jacobian",
                                               "perturbation",
                                               "void_ratio",
                                               "intergranular_strain",
                                               "back_stress",
                                               "fabric"};
constexpr std::string_view coulomb_keys[] = {"friction_coefficient", "tangential_stiffness"};

// [integration] keys that tune Algorithm 1 (no meaning for Coulomb friction).
constexpr std::string_view algorithm1_keys[] = {"interface_newton_jacobian",
                                                "interface_max_newton_iterations",
                                                "polish_iterations",
                                                "adaptive_tolerance",
                                                "band_collapse",
                                                "min_band_fraction"};

template <std::size_t N>
void reject_keys(const TableReader& t, const std::string_view (&keys)[N], const std::string& why) {
    for (const auto& key : keys) {
        if (t.has(key)) {
            t.fail(key, why);
        }
    }
}

struct SampleStart {
    Six stress{};
    double void_ratio = 0.0;
};

SampleStart read_sample(const TableReader& t, InterfaceTestScene& scene) {
    t.allow_only({"model", "parameters", "height", "void_ratio", "stress", "intergranular_strain",
                  "back_stress", "fabric"});
    // The sample is continuum: roughness 1 (kappa concerns the interface only).
    scene.sample_material = read_model_and_parameters(
        t, "hypoplasticity", {"hypoplasticity", "sanisand", "linear-elastic"}, 1.0);
    scene.spec.sample_material = scene.sample_material.choice;
    scene.spec.height = t.number_or("height", 0.02, Bounds::positive());
    SampleStart start;
    start.stress = t.six_numbers("stress");
    if (!(start.stress[0] < 0.0)) {
        t.fail("stress", fmt::format("expected a compressive normal stress s11 < 0 kPa (the "
                                     "initial normal contact stress t_N0 = s11; t_N >= 0 means "
                                     "no contact), got s11 = {} kPa",
                                     start.stress[0]));
    }
    start.void_ratio = t.number("void_ratio", Bounds::positive());
    scene.spec.sample_state = model_state(t, scene.sample_material, start.stress, start.void_ratio);
    return start;
}

void read_continuum_interface(const TableReader& t, InterfaceTestScene& scene,
                              const SampleStart& sample) {
    const std::string f = scene.formulation;
    reject_keys(t, coulomb_keys,
                fmt::format("applies to formulation \"coulomb\" only; expected no such key for "
                            "formulation \"{}\"",
                            f));
    if (f == "novel" && t.has("stutz_initial_stress")) {
        t.fail("stutz_initial_stress", "applies to formulation \"stutz\" only; expected no such "
                                       "key for formulation \"novel\" (its in-plane stresses "
                                       "always start from the sample's)");
    }
    const double roughness = t.number_or("roughness", 0.9, Bounds::open_closed(0.0, 1.0));
    scene.interface_material =
        read_model_and_parameters(t, "hypoplasticity", {"hypoplasticity", "sanisand"}, roughness);
    scene.spec.kind = InterfaceKind::continuum;
    scene.spec.interface_material = scene.interface_material.choice;

    ContactOptions& c = scene.spec.contact;
    InterfaceSettings& s = c.interface;
    s.formulation = f == "novel" ? InterfaceFormulation::novel : InterfaceFormulation::stutz;
    s.ndim = 3;
    s.shear_band_thickness = t.number_or("shear_band_thickness", 0.003, Bounds::positive());
    scene.subincrement = t.choice_or("subincrement", "fixed", {"fixed", "adaptive"});
    s.adaptive = scene.subincrement == "adaptive";
    s.max_subincrement = t.number_or("max_subincrement", 5.0e-6, Bounds::positive());
    s.tolerance = t.number_or("tolerance", 2.0e-3, Bounds::open(0.0, 1.0));
    s.adaptive_tolerance = s.tolerance; // the contract: one tolerance for both unless refined
    scene.jacobian = t.choice_or("jacobian", "perturbation",
                                 {"perturbation", "full-perturbation", "analytical"});
    c.jacobian = scene.jacobian == "perturbation"        ? ContactJacobian::perturbation
                 : scene.jacobian == "full-perturbation" ? ContactJacobian::full_perturbation
                                                         : ContactJacobian::analytical;
    c.perturbation = t.number_or("perturbation", c.perturbation, Bounds::open(0.0, 1.0));

    InterfaceStressStart start = InterfaceStressStart::continuum;
    if (f == "stutz") {
        scene.stutz_initial_stress =
            t.choice_or("stutz_initial_stress", "continuum", {"continuum", "normal-contact"});
        if (scene.stutz_initial_stress == "normal-contact") {
            start = InterfaceStressStart::normal_contact;
        }
    }
    const Six stress = initial_interface_stress(sample.stress, start);
    const double e = t.number_or("void_ratio", sample.void_ratio, Bounds::positive());
    scene.spec.interface_state = model_state(t, scene.interface_material, stress, e);
}

void read_coulomb_interface(const TableReader& t, InterfaceTestScene& scene,
                            const SampleStart& sample) {
    reject_keys(t, continuum_keys,
                "applies to formulations \"novel\" and \"stutz\" only; expected no such key for "
                "formulation \"coulomb\" (friction_coefficient and tangential_stiffness "
                "describe it)");
    scene.spec.kind = InterfaceKind::coulomb;
    CoulombParams& p = scene.spec.coulomb;
    p.friction_coefficient =
        t.number_or("friction_coefficient", p.friction_coefficient, Bounds::non_negative());
    p.tangential_stiffness =
        t.number_or("tangential_stiffness", p.tangential_stiffness, Bounds::positive());
    // The initial shear stress must lie on or inside the friction cone.
    const double tau0 = std::hypot(sample.stress[3], sample.stress[4]);
    const double limit = p.friction_coefficient * std::abs(sample.stress[0]);
    if (tau0 > limit * (1.0 + 1.0e-12)) {
        t.fail("friction_coefficient",
               fmt::format("the sample's initial shear stress |(s12, s13)| = {} kPa exceeds the "
                           "friction limit mu |t_N0| = {} kPa; expected a friction coefficient "
                           ">= {} or a smaller initial shear stress",
                           tau0, limit, tau0 / std::abs(sample.stress[0])));
    }
}

void read_interface(const TableReader& t, InterfaceTestScene& scene, const SampleStart& sample) {
    t.allow_only({"formulation", "model", "parameters", "roughness", "shear_band_thickness",
                  "stutz_initial_stress", "friction_coefficient", "tangential_stiffness",
                  "subincrement", "max_subincrement", "tolerance", "jacobian", "perturbation",
                  "void_ratio", "intergranular_strain", "back_stress", "fabric"});
    scene.formulation = t.choice_or("formulation", "novel", {"novel", "stutz", "coulomb"});
    if (scene.formulation == "coulomb") {
        read_coulomb_interface(t, scene, sample);
    } else {
        read_continuum_interface(t, scene, sample);
    }
}

void read_normal(const TableReader& root, InterfaceTestScene& scene) {
    scene.normal_control = "constant-stress";
    scene.spec.control = NormalControl::constant_stress;
    scene.spec.normal_stiffness = 0.0;
    if (!root.has("normal")) {
        return;
    }
    const TableReader t = root.table("normal");
    t.allow_only({"control", "stiffness", "stiffness_unit"});
    scene.normal_control =
        t.choice_or("control", "constant-stress", {"constant-stress", "constant-stiffness"});
    if (scene.normal_control == "constant-stress") {
        for (const char* key : {"stiffness", "stiffness_unit"}) {
            if (t.has(key)) {
                t.fail(key, "applies to control = \"constant-stiffness\" only; expected no such "
                            "key under constant normal stress");
            }
        }
        return;
    }
    scene.spec.control = NormalControl::constant_stiffness;
    scene.stiffness_given = t.number("stiffness", Bounds::non_negative());
    scene.stiffness_unit = t.choice_or("stiffness_unit", "kPa/m", {"kPa/m", "kPa/mm"});
    scene.spec.normal_stiffness =
        scene.stiffness_unit == "kPa/mm" ? 1000.0 * scene.stiffness_given : scene.stiffness_given;
}

InterfaceStage read_stage(const TableReader& t) {
    t.allow_only({"steps", "du_t1", "du_t2"});
    InterfaceStage stage;
    stage.steps = static_cast<int>(t.integer("steps", 1, 100'000'000));
    stage.du_t1 = t.number_or("du_t1", 0.0);
    stage.du_t2 = t.number_or("du_t2", 0.0);
    return stage;
}

void read_integration(const TableReader& root, InterfaceTestScene& scene) {
    if (!root.has("integration")) {
        return;
    }
    const TableReader t = root.table("integration");
    t.allow_only({"tolerance", "min_pressure", "max_substeps", "newton_tolerance",
                  "max_newton_iterations", "interface_newton_jacobian",
                  "interface_max_newton_iterations", "polish_iterations", "adaptive_tolerance",
                  "band_collapse", "min_band_fraction"});
    InterfaceTestSpec& spec = scene.spec;
    // The continuum models' own integration, for the sample and the interface model alike.
    IntegrationSettings& m = spec.sample_update.settings;
    m.tolerance = t.number_or("tolerance", m.tolerance, Bounds::open(0.0, 1.0));
    m.min_pressure = t.number_or("min_pressure", m.min_pressure, Bounds::positive());
    m.max_substeps = static_cast<int>(t.integer_or("max_substeps", m.max_substeps, 1, 100'000'000));
    spec.contact.interface.model = m;
    spec.newton_tolerance =
        t.number_or("newton_tolerance", spec.newton_tolerance, Bounds::open(0.0, 1.0));
    spec.max_newton_iterations = static_cast<int>(
        t.integer_or("max_newton_iterations", spec.max_newton_iterations, 1, 10'000));
    if (scene.coulomb()) {
        reject_keys(t, algorithm1_keys,
                    "tunes Algorithm 1 of the continuum formulations; expected no such key for "
                    "formulation \"coulomb\"");
        return;
    }
    InterfaceSettings& s = spec.contact.interface;
    s.newton_jacobian =
        t.choice_or("interface_newton_jacobian", "rate", {"rate", "perturbation"}) == "rate"
            ? NewtonJacobian::rate
            : NewtonJacobian::perturbation;
    s.max_newton_iterations = static_cast<int>(
        t.integer_or("interface_max_newton_iterations", s.max_newton_iterations, 1, 10'000));
    s.polish_iterations =
        static_cast<int>(t.integer_or("polish_iterations", s.polish_iterations, 0, 10));
    s.adaptive_tolerance =
        t.number_or("adaptive_tolerance", s.adaptive_tolerance, Bounds::open(0.0, 1.0));
    // Eq. 26 can shrink d_s towards zero: stop there (default) or hold it at its floor.
    s.clamp_band = t.choice_or("band_collapse", "fail", {"fail", "clamp"}) == "clamp";
    s.min_band_fraction =
        t.number_or("min_band_fraction", s.min_band_fraction, Bounds::open(0.0, 1.0));
}

} // namespace

long InterfaceTestScene::total_steps() const {
    long n = 0;
    for (const auto& s : spec.stages) {
        n += s.steps;
    }
    return n;
}

InterfaceTestScene read_interface_test_scene(const toml::table& table, const std::string& file) {
    const TableReader root(table, file, "");
    root.allow_only(
        {"kind", "description", "interface", "sample", "normal", "stage", "integration"});
    InterfaceTestScene scene;
    if (root.has("description")) {
        scene.description = root.string("description");
    }
    // The sample first: the interface starts from its stress and (by default) void ratio.
    const TableReader interface_table = root.table("interface");
    const SampleStart sample = read_sample(root.table("sample"), scene);
    read_interface(interface_table, scene, sample);
    read_normal(root, scene);
    for (const TableReader& st : root.array_of_tables("stage")) {
        scene.spec.stages.push_back(read_stage(st));
    }
    read_integration(root, scene);
    return scene;
}

} // namespace ifsim::io
