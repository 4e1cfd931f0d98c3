#include "io/interface_test/interface_test_scene.hpp"

#include <cmath>
#include <string_view>

#include <fmt/format.h>

#include "io/element_test/element_initial_state.hpp"
#include "io/scene/integration_scheme_reader.hpp"
#include "io/scene/interface_formulation_reader.hpp"
#include "io/scene/table_reader.hpp"

namespace ifsim::io {

namespace {

using Six = std::array<double, 6>;

// [integration] keys that tune Algorithm 1 (no meaning for Coulomb friction).
constexpr std::string_view algorithm1_keys[] = {"interface_newton_jacobian",
                                                "interface_max_newton_iterations",
                                                "interface_newton_fallback",
                                                "interface_newton_line_search",
                                                "polish_iterations",
                                                "adaptive_tolerance",
                                                "band_collapse",
                                                "min_band_fraction"};

struct SampleStart {
    Six stress{};
    double void_ratio = 0.0;
};

SampleStart read_sample(const TableReader& t, InterfaceTestScene& scene) {
    t.allow_only({"model", "parameters", "height", "void_ratio", "stress", "intergranular_strain",
                  "back_stress", "fabric"});
    // The sample is continuum: roughness 1 (kappa concerns the interface only).
    scene.sample_material = read_model_and_parameters(t, Hypoplasticity::name, false, 1.0);
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

// The sample's initial shear stress must lie on or inside the friction cone.
void check_friction_cone(const TableReader& t, const CoulombParams& p, const SampleStart& sample) {
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

// The formulation keys (shared with boundary-value scenes), then the interface's state from
// the sample (continuum formulations) or the friction cone check (Coulomb).
void read_interface(const TableReader& t, InterfaceTestScene& scene, const SampleStart& sample) {
    t.allow_only({"formulation", "model", "parameters", "roughness", "shear_band_thickness",
                  "stutz_initial_stress", "friction_coefficient", "tangential_stiffness",
                  "subincrement", "max_subincrement", "tolerance", "work_newton_iterations",
                  "work_model_substeps", "jacobian", "perturbation", "void_ratio",
                  "intergranular_strain", "back_stress", "fabric"});
    const InterfaceFormulationSpec f = read_interface_formulation(t);
    if (f.is_coulomb()) {
        scene.spec.contact.interface.formulation = InterfaceFormulation::coulomb;
        scene.spec.coulomb = f.coulomb;
        check_friction_cone(t, f.coulomb, sample);
        return;
    }
    scene.stutz_initial_stress = f.stutz_initial_stress;
    scene.interface_material = f.material;
    scene.subincrement = f.subincrement;
    scene.jacobian = f.jacobian;
    scene.spec.interface_material = f.material.choice;
    scene.spec.contact = f.contact;
    scene.spec.contact.interface.ndim = 3;
    const Six stress = initial_interface_stress(sample.stress, f.stress_start);
    const double e = t.number_or("void_ratio", sample.void_ratio, Bounds::positive());
    scene.spec.interface_state = model_state(t, scene.interface_material, stress, e);
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
    // The stagnation acceptance is off unless named: equal to the step tolerance.
    scene.spec.stagnation_tolerance = scene.spec.newton_tolerance;
    if (!root.has("integration")) {
        return;
    }
    const TableReader t = root.table("integration");
    t.allow_only({"tolerance", "min_pressure", "max_substeps", "newton_tolerance",
                  "stagnation_tolerance", "max_newton_iterations", "interface_newton_jacobian",
                  "interface_max_newton_iterations", "interface_newton_fallback",
                  "interface_newton_line_search", "polish_iterations", "adaptive_tolerance",
                  "band_collapse", "min_band_fraction", "scheme", "max_step_substeps"});
    InterfaceTestSpec& spec = scene.spec;
    // The continuum models' own integration, for the sample and the interface model alike.
    IntegrationSettings& m = spec.sample_update.settings;
    m.scheme = read_integration_scheme(t, "scheme", m.scheme);
    m.tolerance = t.number_or("tolerance", m.tolerance, Bounds::open(0.0, 1.0));
    m.min_pressure = t.number_or("min_pressure", m.min_pressure, Bounds::positive());
    m.max_substeps = static_cast<int>(t.integer_or("max_substeps", m.max_substeps, 1, 100'000'000));
    spec.contact.interface.model = m;
    spec.newton_tolerance =
        t.number_or("newton_tolerance", spec.newton_tolerance, Bounds::open(0.0, 1.0));
    // Off unless named: equal to the step tolerance, no stalled step is accepted.
    spec.stagnation_tolerance = spec.newton_tolerance;
    spec.stagnation_tolerance =
        t.number_or("stagnation_tolerance", spec.stagnation_tolerance, Bounds::open(0.0, 1.0));
    if (spec.stagnation_tolerance < spec.newton_tolerance) {
        t.fail("stagnation_tolerance",
               fmt::format("expected at least newton_tolerance ({:g}): a stalled step is accepted "
                           "only above the tolerance it failed to reach",
                           spec.newton_tolerance));
    }
    spec.max_newton_iterations = static_cast<int>(
        t.integer_or("max_newton_iterations", spec.max_newton_iterations, 1, 10'000));
    spec.max_step_substeps =
        t.number_or("max_step_substeps", spec.max_step_substeps, Bounds::positive());
    if (scene.coulomb()) {
        t.reject(algorithm1_keys, algorithm1_key_with_coulomb);
        return;
    }
    InterfaceSettings& s = spec.contact.interface;
    s.newton_jacobian =
        t.choice_or("interface_newton_jacobian", "rate", {"rate", "perturbation"}) == "rate"
            ? NewtonJacobian::rate
            : NewtonJacobian::perturbation;
    s.max_newton_iterations = static_cast<int>(
        t.integer_or("interface_max_newton_iterations", s.max_newton_iterations, 1, 10'000));
    s.newton_fallback = t.boolean_or("interface_newton_fallback", s.newton_fallback);
    s.newton_line_search =
        static_cast<int>(t.integer_or("interface_newton_line_search", s.newton_line_search, 0, 60));
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
