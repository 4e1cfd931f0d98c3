#include "io/boundary_value/boundary_value_scene.hpp"

#include <cmath>
#include <optional>

#include <fmt/format.h>

#include "io/boundary_value/boundary_value_region.hpp"
#include "io/boundary_value/boundary_value_stage.hpp"
#include "io/scene/table_reader.hpp"

namespace ifsim::io {

namespace {

void read_solver(const TableReader& root, BoundaryValueScene& scene) {
    fem::SolverSettings& s = scene.settings;
    scene.linear_solver = "umfpack";
    scene.tangent = "perturbation";
    if (!root.has("solver")) {
        return;
    }
    const TableReader t = root.table("solver");
    t.allow_only({"residual_tolerance",
                  "displacement_tolerance",
                  "max_iterations",
                  "max_cuts",
                  "growth_after",
                  "carry_cuts",
                  "max_line_search",
                  "stagnation_tolerance",
                  "gather_tolerance",
                  "max_gathers",
                  "gather_relaxation",
                  "early_gather_residual",
                  "hold_slip_viscosity",
                  "linear_solver",
                  "tangent",
                  "predictor",
                  "extrapolate",
                  "check_tangent",
                  "max_step_substeps",
                  "divergence_check",
                  "reuse_factorisation",
                  "krylov_tolerance",
                  "krylov_max_iterations",
                  "krylov_factorisation_cost",
                  "preconditioner_precision"});
    s.residual_tolerance =
        t.number_or("residual_tolerance", s.residual_tolerance, Bounds::open(0.0, 1.0));
    s.displacement_tolerance =
        t.number_or("displacement_tolerance", s.displacement_tolerance, Bounds::open(0.0, 1.0));
    s.max_iterations = static_cast<int>(t.integer_or("max_iterations", s.max_iterations, 1, 1000));
    s.max_cuts = static_cast<int>(t.integer_or("max_cuts", s.max_cuts, 0, 30));
    s.max_step_substeps = t.number_or("max_step_substeps", s.max_step_substeps, Bounds::positive());
    s.growth_after = static_cast<int>(t.integer_or("growth_after", s.growth_after, 1, 1000));
    s.carry_cuts = static_cast<int>(t.integer_or("carry_cuts", s.carry_cuts, 0, 1000));
    s.max_line_search = static_cast<int>(t.integer_or("max_line_search", s.max_line_search, 0, 30));
    s.stagnation_tolerance =
        t.number_or("stagnation_tolerance", s.stagnation_tolerance, Bounds::closed_open(0.0, 1.0));
    s.gather_tolerance =
        t.number_or("gather_tolerance", s.gather_tolerance, Bounds::open(0.0, 1.0));
    s.max_gathers = static_cast<int>(t.integer_or("max_gathers", s.max_gathers, 0, 1000));
    s.gather_aitken = t.choice_or("gather_relaxation", s.gather_aitken ? "aitken" : "none",
                                  {"none", "aitken"}) == "aitken";
    s.early_gather_residual = t.number_or("early_gather_residual", s.early_gather_residual,
                                          Bounds::closed_open(0.0, 1.0));
    s.check_tangent = t.boolean_or("check_tangent", false);
    s.divergence_check = t.boolean_or("divergence_check", s.divergence_check);
    s.hold_slip_viscosity = t.boolean_or("hold_slip_viscosity", s.hold_slip_viscosity);
    s.reuse_factorisation = t.boolean_or("reuse_factorisation", s.reuse_factorisation);
    s.krylov_tolerance =
        t.number_or("krylov_tolerance", s.krylov_tolerance, Bounds::open(0.0, 1.0));
    s.krylov_max_iterations =
        static_cast<int>(t.integer_or("krylov_max_iterations", s.krylov_max_iterations, 1, 1000));
    s.krylov_factorisation_cost = t.number_or("krylov_factorisation_cost",
                                              s.krylov_factorisation_cost, Bounds::non_negative());
    s.preconditioner_precision =
        t.choice_or("preconditioner_precision", "double", {"double", "single"}) == "single"
            ? fem::LuPrecision::single_precision
            : fem::LuPrecision::double_precision;
    scene.linear_solver = t.choice_or("linear_solver", "umfpack", {"umfpack", "klu"});
    s.linear_solver = scene.linear_solver == "umfpack" ? fem::LinearSolverKind::umfpack
                                                       : fem::LinearSolverKind::klu;
    scene.tangent =
        t.choice_or("tangent", "perturbation", {"perturbation", "fixed-substeps", "rate"});
    s.tangent.kind = scene.tangent == "rate" ? TangentKind::rate : TangentKind::perturbation;
    s.tangent.fixed_substeps = scene.tangent == "fixed-substeps";
    if (t.has("predictor") && t.has("extrapolate")) {
        t.fail("extrapolate", "give either predictor or the older extrapolate, not both");
    }
    scene.predictor = t.choice_or("predictor", "extrapolated", {"extrapolated", "tangent", "zero"});
    if (t.has("extrapolate")) { // older key: false meant free DOFs starting at zero
        scene.predictor = t.boolean_or("extrapolate", true) ? "extrapolated" : "zero";
    }
    s.predictor = scene.predictor == "tangent" ? fem::Predictor::tangent
                  : scene.predictor == "zero"  ? fem::Predictor::zero
                                               : fem::Predictor::extrapolated;
}

// [output] contact: the name of a pair; the first pair by default.
std::size_t main_contact(const TableReader& t,
                         const std::vector<BoundaryValueInterface>& contacts) {
    if (!t.has("contact")) {
        return 0;
    }
    if (contacts.empty()) {
        t.fail("contact", "applies to runs with contact pairs ([interface] or [[contact]]) "
                          "only; expected no such key");
    }
    const std::string name = t.string("contact");
    std::string list;
    for (std::size_t k = 0; k < contacts.size(); ++k) {
        if (contacts[k].pair.name == name) {
            return k;
        }
        list += fmt::format("{}\"{}\"", list.empty() ? "" : ", ", contacts[k].pair.name);
    }
    t.fail("contact",
           fmt::format("expected the name of a contact pair: {}; got \"{}\"", list, name));
}

// [output] fields: true (the end of every stage), or a table { every = N, stages = true|false,
// times = [t, ...] } whose stages default to true.
FieldSchedule read_fields(const TableReader& t) {
    FieldSchedule f;
    if (!t.has("fields")) {
        return f;
    }
    const toml::node* node = t.find("fields");
    if (node->is_boolean()) {
        f.stages = t.boolean_or("fields", false);
        return f;
    }
    if (!node->is_table()) {
        t.fail("fields", "expected true, false or a table { every = N, stages = true, times = "
                         "[t1, t2] }");
    }
    const TableReader ft = t.table("fields");
    ft.allow_only({"every", "stages", "times"});
    f.every = static_cast<long>(ft.integer_or("every", 0, 0, 1'000'000'000));
    f.stages = ft.boolean_or("stages", true);
    if (ft.has("times")) {
        const toml::array* times = ft.find("times")->as_array();
        if (times == nullptr) {
            ft.fail("times", "expected a list of times (the history's time column), e.g. "
                             "[1.5, 2.0]");
        }
        for (const toml::node& v : *times) {
            const std::optional<double> x = v.value<double>();
            if (!x || !std::isfinite(*x) || *x < 0.0) {
                ft.fail("times", "expected finite times >= 0 (the history's time column)");
            }
            f.times.push_back(*x);
        }
    }
    return f;
}

BoundaryValueOutput read_output(const TableReader& t, const fem::Mesh& mesh,
                                const std::vector<BoundaryValueInterface>& contacts) {
    t.allow_only({"plate", "soil_top", "traction_faces", "contact", "fields"});
    BoundaryValueOutput out;
    out.fields = read_fields(t);
    out.plate = read_node_set(t, "plate", mesh);
    out.soil_top = read_node_set(t, "soil_top", mesh);
    out.contact = main_contact(t, contacts);
    if (!contacts.empty()) {
        if (t.has("traction_faces")) {
            t.fail("traction_faces", "applies to runs without [interface] or [[contact]] only "
                                     "(with them the tractions are the contact's); expected no "
                                     "such key");
        }
        return out;
    }
    out.traction_faces = t.string("traction_faces");
    if (!mesh.face_sets.contains(out.traction_faces) ||
        mesh.face_sets.at(out.traction_faces).empty()) {
        t.fail("traction_faces", fmt::format("expected a face set of the mesh (\"<body>.<side>\") "
                                             "whose reactions give the mean traction, got \"{}\"",
                                             out.traction_faces));
    }
    return out;
}

// [[body]] blocks: the structured mesh and a material per body.
void read_bodies(const TableReader& root, const std::vector<std::string>& names,
                 BoundaryValueScene& scene) {
    if (root.has("region")) {
        root.fail("region", "applies to a mesh file ([mesh] file = \"path.msh\") only; expected "
                            "no [[region]] with [[body]] blocks (each body names its material)");
    }
    if (!root.has("body")) {
        root.fail("body", "missing; expected one or more tables [[body]] (structured blocks) or "
                          "a Gmsh mesh file ([mesh] file = \"path.msh\") with [[region]] entries");
    }
    const TableReader material = root.table("material");
    for (const TableReader& b : root.array_of_tables("body")) {
        BodySpec body = read_body(b, scene.mesh_spec.dimension, names);
        for (const BodySpec& other : scene.bodies) {
            if (other.name == body.name) {
                b.fail("name", fmt::format("expected a name not used by another body, got \"{}\"",
                                           body.name));
            }
        }
        scene.materials.emplace(body.name, read_body_material(material.table(body.material), body));
        scene.bodies.push_back(std::move(body));
    }
    scene.mesh = build_mesh(scene.bodies, scene.mesh_spec.dimension);
}

// [mesh] file: the file's mesh and a material per [[region]].
void read_mesh_file_and_regions(const TableReader& root, const TableReader& mesh,
                                const std::vector<std::string>& names, BoundaryValueScene& scene) {
    if (root.has("body")) {
        root.fail("body", "expected either [[body]] blocks or a mesh file ([mesh] file), not both");
    }
    if (!root.has("region")) {
        root.fail("region", "missing; expected one or more tables [[region]] (set = an element "
                            "set of the mesh file, material = a key of [material]) with [mesh] "
                            "file");
    }
    scene.mesh = read_mesh_file(mesh, scene.mesh_spec);
    scene.bodies = read_regions(root, scene.mesh, names);
    const TableReader material = root.table("material");
    for (const BodySpec& region : scene.bodies) {
        scene.materials.emplace(region.name,
                                read_body_material(material.table(region.material), region));
    }
}

} // namespace

std::string read_node_set(const TableReader& t, std::string_view key, const fem::Mesh& mesh) {
    const std::string name = t.string(key);
    if (!mesh.node_sets.contains(name)) {
        std::string list;
        for (const auto& [n, nodes] : mesh.node_sets) {
            list += fmt::format("{}\"{}\"", list.empty() ? "" : ", ", n);
        }
        t.fail(key, fmt::format("expected a node set of the mesh: {}; got \"{}\"", list, name));
    }
    return name;
}

const BoundaryValueInterface* BoundaryValueScene::main_contact() const {
    return contacts.empty() ? nullptr : &contacts.at(output.contact);
}

long BoundaryValueScene::total_steps() const {
    long n = 0;
    for (const auto& s : stages) {
        n += s.steps;
    }
    return n;
}

std::vector<fem::ElementSetMaterial> BoundaryValueScene::set_materials() const {
    std::vector<fem::ElementSetMaterial> out;
    for (const BodySpec& b : bodies) {
        out.push_back(materials.at(b.name).set);
    }
    return out;
}

BoundaryValueScene read_boundary_value_scene(const toml::table& table, const std::string& file) {
    const TableReader root(table, file, "");
    root.allow_only({"kind", "description", "mesh", "body", "region", "material", "interface",
                     "contact", "solver", "output", "recorder", "stage"});
    BoundaryValueScene scene;
    if (root.has("description")) {
        scene.description = root.string("description");
    }
    const TableReader mesh = root.table("mesh");
    scene.mesh_spec = read_mesh_spec(mesh);
    scene.settings.integration = scene.mesh_spec.rule;
    scene.settings.kinematics = scene.mesh_spec.kinematics == "updated-lagrangian"
                                    ? fem::Kinematics::updated_lagrangian
                                    : fem::Kinematics::small_strain;

    const TableReader material = root.table("material");
    const std::vector<std::string> names = material.keys();
    if (names.empty()) {
        material.fail_here("expected one or more tables [material.NAME]");
    }
    if (scene.mesh_spec.file.empty()) {
        read_bodies(root, names, scene);
    } else {
        read_mesh_file_and_regions(root, mesh, names, scene);
    }

    scene.contacts = read_boundary_value_contacts(root, scene.mesh, scene.materials);
    read_solver(root, scene);
    scene.output = read_output(root.table("output"), scene.mesh, scene.contacts);
    scene.recorders = read_recorders(root, scene.mesh, scene.contacts);
    int number = 1;
    for (const TableReader& st : root.array_of_tables("stage")) {
        scene.stages.push_back(read_boundary_value_stage(st, scene.mesh, number++));
    }
    return scene;
}

} // namespace ifsim::io
