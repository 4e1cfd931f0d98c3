#include "io/boundary_value/boundary_value_stage.hpp"

#include <stdexcept>

#include <fmt/format.h>

#include "fem/dof_map.hpp"
#include "io/mesh/face_geometry.hpp"

namespace ifsim::io {

namespace {

template <class Sets>
std::string set_names(const Sets& sets) {
    std::string list;
    for (const auto& [name, members] : sets) {
        if (name.find('#') == std::string::npos) {
            list += fmt::format("{}\"{}\"", list.empty() ? "" : ", ", name);
        }
    }
    return list;
}

std::string node_set(const TableReader& t, const fem::Mesh& mesh) {
    const std::string name = t.string("nodes");
    if (!mesh.node_sets.contains(name)) {
        t.fail("nodes", fmt::format("expected a node set of the mesh: {}; got \"{}\"",
                                    set_names(mesh.node_sets), name));
    }
    return name;
}

std::string face_set(const TableReader& t, const fem::Mesh& mesh) {
    const std::string name = t.string("faces");
    if (!mesh.face_sets.contains(name) || mesh.face_sets.at(name).empty()) {
        t.fail("faces", fmt::format("expected a face set of the mesh: {}; got \"{}\"",
                                    set_names(mesh.face_sets), name));
    }
    return name;
}

int direction(const TableReader& t, int dim) {
    const std::string d = dim == 2 ? t.choice_or("direction", "", {"x", "y"})
                                   : t.choice_or("direction", "", {"x", "y", "z"});
    return d == "x" ? 0 : d == "y" ? 1 : 2;
}

std::vector<TableReader> entries(const TableReader& t, std::string_view key) {
    return t.has(key) ? t.array_of_tables(key) : std::vector<TableReader>{};
}

} // namespace

fem::Stage read_boundary_value_stage(const TableReader& t, fem::Mesh& mesh, int number) {
    t.allow_only({"name", "steps", "displacement", "equal", "pressure", "spring", "gravity"});
    fem::Stage stage;
    stage.name = t.has("name") ? t.string("name") : fmt::format("stage {}", number);
    stage.steps = static_cast<int>(t.integer("steps", 1, 100'000'000));
    const int dim = mesh.dim();
    for (const TableReader& e : entries(t, "displacement")) {
        e.allow_only({"nodes", "direction", "change"});
        stage.displacements.push_back(
            {node_set(e, mesh), direction(e, dim), e.number_or("change", 0.0)});
    }
    for (const TableReader& e : entries(t, "equal")) {
        e.allow_only({"nodes", "direction"});
        stage.equal_displacements.push_back({node_set(e, mesh), direction(e, dim)});
    }
    for (const TableReader& e : entries(t, "pressure")) {
        e.allow_only({"faces", "from", "to"});
        fem::FacePressure p;
        p.face_set = face_set(e, mesh);
        p.from = e.number("from");
        p.to = e.number_or("to", p.from);
        stage.pressures.push_back(p);
    }
    for (const TableReader& e : entries(t, "spring")) {
        e.allow_only({"faces", "direction", "stiffness", "stiffness_unit"});
        const std::string faces = face_set(e, mesh);
        const int d = direction(e, dim);
        const double k = e.number("stiffness", Bounds::non_negative());
        const std::string unit = e.choice_or("stiffness_unit", "kPa/m", {"kPa/m", "kPa/mm"});
        const std::string nodes = faces + "#nodes";
        mesh.node_sets[nodes] = mesh.nodes_of_faces(faces);
        const double per_m = unit == "kPa/mm" ? 1000.0 * k : k;
        stage.springs.push_back({nodes, d, per_m * face_set_geometry(mesh, faces).area});
    }
    if (t.has("gravity")) {
        const TableReader g = t.table("gravity");
        g.allow_only({"from", "to"});
        fem::GravityRamp r;
        r.from = g.number("from");
        r.to = g.number_or("to", r.from);
        stage.gravity = r;
    }
    try {
        fem::build_dof_map(mesh, stage);
    } catch (const std::exception& e) {
        t.fail_here(
            fmt::format("expected constraints that do not contradict each other: {}", e.what()));
    }
    return stage;
}

} // namespace ifsim::io
