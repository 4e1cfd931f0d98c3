#include "io/scene/interface_formulation_reader.hpp"

#include <array>
#include <string_view>
#include <utility>

#include <fmt/format.h>

namespace ifsim::io {

namespace {

// [interface] keys of the continuum formulations (novel, stutz) and of Coulomb friction.
constexpr std::string_view continuum_keys[] = {"model",
                                               "parameters",
                                               "roughness",
                                               "shear_band_thickness",
                                               "stutz_initial_stress",
                                               "subincrement",
                                               "max_subincrement",
                                               "tolerance",
                                               "work_newton_iterations",
                                               "work_model_substeps",
                                               "jacobian",
                                               "perturbation",
                                               "open_threshold",
                                               "void_ratio",
                                               "intergranular_strain",
                                               "back_stress",
                                               "fabric"};
constexpr std::string_view coulomb_keys[] = {"friction_coefficient", "tangential_stiffness"};

constexpr std::array<std::pair<InterfaceFormulation, std::string_view>, 3> names{
    {{InterfaceFormulation::novel, "novel"},
     {InterfaceFormulation::stutz, "stutz"},
     {InterfaceFormulation::coulomb, "coulomb"}}};

void read_continuum(const TableReader& t, InterfaceFormulationSpec& spec) {
    const std::string f = spec.name();
    t.reject(coulomb_keys,
             fmt::format("applies to formulation \"coulomb\" only; expected no such key for "
                         "formulation \"{}\"",
                         f));
    if (f == "novel" && t.has("stutz_initial_stress")) {
        t.fail("stutz_initial_stress", "applies to formulation \"stutz\" only; expected no such "
                                       "key for formulation \"novel\" (its in-plane stresses "
                                       "always start from the continuum's)");
    }
    const double roughness = t.number_or("roughness", 0.9, Bounds::open_closed(0.0, 1.0));
    spec.material = read_model_and_parameters(t, Hypoplasticity::name, true, roughness);

    ContactOptions& c = spec.contact;
    InterfaceSettings& s = c.interface;
    s.formulation = spec.formulation;
    s.shear_band_thickness = t.number_or("shear_band_thickness", 0.003, Bounds::positive());
    spec.subincrement = t.choice_or("subincrement", "fixed", {"fixed", "adaptive"});
    s.adaptive = spec.subincrement == "adaptive";
    s.max_subincrement = t.number_or("max_subincrement", 5.0e-6, Bounds::positive());
    s.tolerance = t.number_or("tolerance", 2.0e-3, Bounds::open(0.0, 1.0));
    s.adaptive_tolerance = s.tolerance; // the contract: one tolerance for both unless refined
    // The work bound of the adaptive sub-increments (kernels/interface_settings.hpp).
    s.work_newton_iterations =
        t.number_or("work_newton_iterations", s.work_newton_iterations, Bounds::non_negative());
    s.work_model_substeps =
        t.number_or("work_model_substeps", s.work_model_substeps, Bounds::non_negative());
    spec.jacobian = t.choice_or(
        "jacobian", "perturbation",
        {"perturbation", "central", "full-perturbation", "analytical", "perturbation-one-side"});
    contact_jacobian_from_name(spec.jacobian, c.jacobian);
    c.perturbation = t.number_or("perturbation", c.perturbation, Bounds::open(0.0, 1.0));
    s.open_threshold = t.number_or("open_threshold", s.open_threshold, Bounds::positive());

    spec.stress_start = InterfaceStressStart::continuum;
    if (f == "stutz") {
        spec.stutz_initial_stress =
            t.choice_or("stutz_initial_stress", "continuum", {"continuum", "normal-contact"});
        if (spec.stutz_initial_stress == "normal-contact") {
            spec.stress_start = InterfaceStressStart::normal_contact;
        }
    }
}

void read_coulomb(const TableReader& t, InterfaceFormulationSpec& spec) {
    t.reject(continuum_keys,
             "applies to formulations \"novel\" and \"stutz\" only; expected no such key for "
             "formulation \"coulomb\" (friction_coefficient and tangential_stiffness "
             "describe it)");
    CoulombParams& p = spec.coulomb;
    p.friction_coefficient =
        t.number_or("friction_coefficient", p.friction_coefficient, Bounds::non_negative());
    p.tangential_stiffness =
        t.number_or("tangential_stiffness", p.tangential_stiffness, Bounds::positive());
}

} // namespace

std::string_view formulation_name(InterfaceFormulation f) {
    for (const auto& [value, name] : names) {
        if (value == f) {
            return name;
        }
    }
    return "unknown";
}

std::string InterfaceFormulationSpec::name() const {
    return std::string(formulation_name(formulation));
}

InterfaceFormulationSpec read_interface_formulation(const TableReader& t) {
    InterfaceFormulationSpec spec;
    std::array<std::string_view, names.size()> choices{};
    for (std::size_t i = 0; i < names.size(); ++i) {
        choices[i] = names[i].second;
    }
    const std::string chosen = t.choice_or("formulation", "novel", choices);
    for (const auto& [value, name] : names) {
        if (chosen == name) {
            spec.formulation = value;
        }
    }
    if (spec.is_coulomb()) {
        read_coulomb(t, spec);
    } else {
        read_continuum(t, spec);
    }
    return spec;
}

} // namespace ifsim::io
