#include "io/boundary_value/boundary_value_interface.hpp"

#include <cmath>
#include <limits>
#include <memory>

#include <fmt/format.h>

#include "io/element_test/element_initial_state.hpp"
#include "io/interface_test/interface_initial_stress.hpp"

namespace ifsim::io {

namespace {

using Six = std::array<double, 6>;

std::string face_set_names(const fem::Mesh& mesh) {
    std::string list;
    for (const auto& [name, faces] : mesh.face_sets) {
        list += fmt::format("{}\"{}\"", list.empty() ? "" : ", ", name);
    }
    return list;
}

std::string read_face_set(const TableReader& t, std::string_view key, const fem::Mesh& mesh) {
    const std::string name = t.string(key);
    if (!mesh.face_sets.contains(name) || mesh.face_sets.at(name).empty()) {
        t.fail(key, fmt::format("expected a face set of the mesh (\"<body>.<side>\"): {}; got "
                                "\"{}\"",
                                face_set_names(mesh), name));
    }
    return name;
}

// The body (element set) the first slave face belongs to.
std::string body_of_faces(const fem::Mesh& mesh, const std::string& faces,
                          const std::map<std::string, BodyMaterial>& materials) {
    const int element = mesh.face_set(faces).front().element;
    for (const auto& [body, m] : materials) {
        const auto& set = mesh.element_set(body);
        if (std::find(set.begin(), set.end(), element) != set.end()) {
            return body;
        }
    }
    return {};
}

// A body's global stress seen from a horizontal interface below it (local 1 = vertical):
// only for checking the interface's state keys at parse time.
Six vertical_local(const Six& s, int dim) {
    if (dim == 2) {
        return {s[1], s[0], s[2], s[3], 0.0, 0.0};
    }
    return {s[2], s[0], s[1], s[4], s[5], s[3]};
}

// The interface state function: captures a copy of the [interface] table so that model_state
// reads its keys (and reports their errors with file and key) whenever a point is initialised.
fem::InterfaceStateFromStress state_function(const TableReader& t, const MaterialSpec& material,
                                             InterfaceStressStart start, double void_ratio) {
    auto table = std::make_shared<const toml::table>(t.toml_table());
    return [table, file = t.file(), path = t.path(), material, start,
            void_ratio](const fem::Voigt6& local) {
        const TableReader r(*table, file, path);
        const Six stress = initial_interface_stress(local, start);
        const double e = r.number_or("void_ratio", void_ratio, Bounds::positive());
        return model_state(r, material, stress, e);
    };
}

} // namespace

const std::vector<std::string_view>& boundary_value_interface_keys() {
    static const std::vector<std::string_view> keys = {"slave",
                                                       "master",
                                                       "normal_penalty",
                                                       "initial_contact",
                                                       "shear_direction",
                                                       "formulation",
                                                       "model",
                                                       "parameters",
                                                       "roughness",
                                                       "shear_band_thickness",
                                                       "stutz_initial_stress",
                                                       "friction_coefficient",
                                                       "tangential_stiffness",
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
                                                       "fabric",
                                                       "model_tolerance",
                                                       "model_integration",
                                                       "newton_jacobian",
                                                       "newton_fallback",
                                                       "newton_switch_ratio",
                                                       "newton_switch_jacobian",
                                                       "newton_line_search",
                                                       "jacobian_tolerance",
                                                       "polish_iterations",
                                                       "adaptive_partition",
                                                       "defer_jacobian",
                                                       "slip_viscosity",
                                                       "slip_viscosity_use"};
    return keys;
}

BoundaryValueInterface
read_boundary_value_interface(const TableReader& t, const fem::Mesh& mesh,
                              const std::map<std::string, BodyMaterial>& materials) {
    t.allow_only(boundary_value_interface_keys());
    return read_boundary_value_pair(t, "interface", mesh, materials);
}

BoundaryValueInterface
read_boundary_value_pair(const TableReader& t, const std::string& name, const fem::Mesh& mesh,
                         const std::map<std::string, BodyMaterial>& materials) {
    BoundaryValueInterface out;
    fem::ContactPairSpec& pair = out.pair;
    pair.name = name;
    pair.slave_faces = read_face_set(t, "slave", mesh);
    pair.master_faces = read_face_set(t, "master", mesh);
    out.slave_body = body_of_faces(mesh, pair.slave_faces, materials);
    if (out.slave_body == body_of_faces(mesh, pair.master_faces, materials)) {
        t.fail("master", fmt::format("expected faces of another body than the slave faces (both "
                                     "belong to body \"{}\")",
                                     out.slave_body));
    }
    pair.normal_penalty = t.number_or("normal_penalty", pair.normal_penalty, Bounds::positive());
    out.initial_contact =
        t.choice_or("initial_contact", "prestressed", {"prestressed", "geometric"});
    pair.prestressed = out.initial_contact == "prestressed";
    if (t.has("shear_direction")) {
        const auto d = t.numbers("shear_direction", 3, Bounds::any(), "x, y, z in global axes");
        if (!(std::hypot(d[0], d[1], d[2]) > 0.0)) {
            t.fail("shear_direction", "expected a non-zero vector");
        }
        pair.shear_direction = {d[0], d[1], d[2]};
    }

    out.formulation = read_interface_formulation(t);
    const InterfaceFormulationSpec& f = out.formulation;
    if (f.is_coulomb()) {
        constexpr std::string_view algorithm1_keys[] = {
            "model_tolerance",        "model_integration", "newton_jacobian",
            "jacobian_tolerance",     "polish_iterations", "adaptive_partition",
            "defer_jacobian",         "newton_fallback",   "newton_switch_ratio",
            "newton_switch_jacobian", "newton_line_search"};
        t.reject(algorithm1_keys, algorithm1_key_with_coulomb);
        constexpr std::string_view viscosity_key[] = {"slip_viscosity", "slip_viscosity_use"};
        t.reject(viscosity_key, "regularises a continuum interface band past its peak; "
                                "expected no such key for formulation \"coulomb\" (its "
                                "friction does not soften)");
        pair.options.interface.formulation = InterfaceFormulation::coulomb;
        pair.friction = f.coulomb;
        return out;
    }
    const BodyMaterial& soil = materials.at(out.slave_body);
    if (soil.spec.model == LinearElastic::name) {
        t.fail("slave", fmt::format("expected the soil's faces as slave: the continuum stress and "
                                    "void ratio of body \"{}\" (linear-elastic) cannot start a "
                                    "continuum interface",
                                    out.slave_body));
    }
    pair.interface_material = f.material.choice;
    pair.options = f.contact;
    // The inner solves' tolerances set the noise of the Eq. 37 differences (docs/interface.md).
    InterfaceSettings& is = pair.options.interface;
    is.model.tolerance = t.number_or("model_tolerance", is.model.tolerance, Bounds::open(0.0, 1.0));
    // Backward-Euler steps instead of explicit substeps: Sanisand only
    // (kernels/sanisand_implicit.hpp).
    is.model.backward_euler =
        t.choice_or("model_integration", "explicit", {"explicit", "implicit"}) == "implicit";
    if (is.model.backward_euler && !std::holds_alternative<SanisandParams>(f.material.choice)) {
        t.fail("model_integration", "\"explicit\" with this interface model (backward-Euler "
                                    "steps exist for model \"sanisand\" only)");
    }
    is.newton_jacobian = t.choice_or("newton_jacobian", "rate", {"rate", "perturbation"}) == "rate"
                             ? NewtonJacobian::rate
                             : NewtonJacobian::perturbation;
    // With the rate Jacobian: a point whose Newton fails gets a second try on the difference
    // Jacobian.
    is.newton_fallback = t.boolean_or("newton_fallback", is.newton_fallback);
    // With the rate Jacobian: a lane whose Newton creeps goes on with the difference Jacobian.
    is.newton_switch_ratio =
        t.number_or("newton_switch_ratio", is.newton_switch_ratio, Bounds::closed_open(0.0, 1.0));
    // What it switches to: Broyden's updates (no more evaluations, but iterates that can jump
    // far off) or the perturbation Jacobian (k + 1 evaluations per iteration).
    is.newton_switch_broyden =
        t.choice_or("newton_switch_jacobian", "broyden", {"broyden", "perturbation"}) == "broyden";
    // Halvings of a Newton step that does not lower Algorithm 1's residual (0: plain Newton).
    is.newton_line_search =
        static_cast<int>(t.integer_or("newton_line_search", is.newton_line_search, 0, 60));
    is.jacobian_tolerance =
        t.number_or("jacobian_tolerance", is.jacobian_tolerance, Bounds::closed_open(0.0, 1.0));
    is.polish_iterations =
        static_cast<int>(t.integer_or("polish_iterations", is.polish_iterations, 0, 10));
    // Adaptive sub-increments held through an increment's Newton iterations or chosen anew in
    // each (docs/fem.md).
    pair.hold_partition =
        t.choice_or("adaptive_partition", "increment", {"increment", "iteration"}) == "increment";
    // Eq. 37's lanes only when the solver asks for the tangent, not in every residual pass.
    pair.defer_jacobian = t.boolean_or("defer_jacobian", pair.defer_jacobian);
    // A viscous shear traction for bands past their peak under load control (docs/fem.md).
    pair.slip_viscosity =
        t.number_or("slip_viscosity", pair.slip_viscosity,
                    Bounds::closed_open(0.0, std::numeric_limits<double>::infinity()));
    // Without a slip_viscosity key the use names nothing; with one set to 0 (e.g. by --set on a
    // scene that has one) it is moot and allowed.
    if (t.has("slip_viscosity_use") && !t.has("slip_viscosity")) {
        t.fail("slip_viscosity_use", "a slip_viscosity beside it (without one there is no "
                                     "viscosity to use)");
    }
    pair.slip_viscosity_always =
        t.choice_or("slip_viscosity_use", "always", {"always", "retry"}) == "always";
    pair.initial_state = state_function(t, f.material, f.stress_start, soil.void_ratio);
    // Check the state keys now, with the slave body's initial stress.
    pair.initial_state(vertical_local(soil.stress, mesh.dim()));
    return out;
}

} // namespace ifsim::io
