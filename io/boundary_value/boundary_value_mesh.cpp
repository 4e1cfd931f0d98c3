#include "io/boundary_value/boundary_value_mesh.hpp"

#include <algorithm>
#include <cctype>

#include <fmt/format.h>

#include "fem/structured_mesh.hpp"
#include "io/mesh/gmsh_error.hpp"
#include "io/mesh/gmsh_reader.hpp"

namespace ifsim::io {

namespace {

std::string quoted_list(const std::vector<std::string>& names) {
    std::string list;
    for (const auto& n : names) {
        list += fmt::format("{}\"{}\"", list.empty() ? "" : ", ", n);
    }
    return list;
}

} // namespace

MeshSpec read_mesh_spec(const TableReader& t) {
    t.allow_only({"dimension", "integration", "file", "kinematics"});
    MeshSpec spec;
    spec.dimension = static_cast<int>(t.integer("dimension", 2, 3));
    spec.integration = t.choice_or("integration", "full", {"full", "reduced"});
    spec.rule = spec.integration == "full" ? fem::Integration::full : fem::Integration::reduced;
    spec.kinematics =
        t.choice_or("kinematics", "small-strain", {"small-strain", "updated-lagrangian"});
    if (t.has("file")) {
        spec.file = t.string("file");
        if (spec.file.empty()) {
            t.fail("file", "expected the path of a Gmsh .msh file, got an empty string");
        }
        const std::filesystem::path p(spec.file);
        spec.path = p.is_absolute() ? p : std::filesystem::path(t.file()).parent_path() / p;
    }
    return spec;
}

fem::Mesh read_mesh_file(const TableReader& t, const MeshSpec& spec) {
    GmshMesh read;
    try {
        read = read_gmsh_mesh(spec.path.string());
    } catch (const MeshFileError& e) {
        t.fail("file",
               fmt::format("expected a readable Gmsh mesh (MSH 4.1 or 2.2, ASCII or binary, of "
                           "quadrangles or hexahedra): {}",
                           e.what()));
    }
    if (read.mesh.dim() != spec.dimension) {
        t.fail("dimension", fmt::format("expected the dimension of the mesh file {} ({}), got {}",
                                        spec.path.string(), read.mesh.dim(), spec.dimension));
    }
    return std::move(read.mesh);
}

BodySpec read_body(const TableReader& t, int dimension, const std::vector<std::string>& materials) {
    t.allow_only({"name", "material", "origin", "size", "elements"});
    BodySpec body;
    body.name = t.string("name");
    const bool valid_name =
        !body.name.empty() && std::all_of(body.name.begin(), body.name.end(), [](char c) {
            return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
        });
    if (!valid_name) {
        t.fail("name", fmt::format("expected a non-empty name of letters, digits, '_' and '-' "
                                   "(it prefixes the body's sets, \"<name>.top\"), got \"{}\"",
                                   body.name));
    }
    body.material = t.string("material");
    if (std::find(materials.begin(), materials.end(), body.material) == materials.end()) {
        t.fail("material", fmt::format("expected the name of a [material.NAME] table ({}), got "
                                       "\"{}\"",
                                       quoted_list(materials), body.material));
    }
    const bool three = dimension == 3;
    const auto n = static_cast<std::size_t>(dimension);
    body.origin = t.numbers("origin", n, Bounds::any(),
                            three ? "lower corner x, y, z in m" : "lower corner x, y in m");
    body.size = t.numbers("size", n, Bounds::positive(),
                          three ? "width, depth, height in m" : "width, height in m");
    body.elements = t.integers("elements", n, 1, 100'000,
                               three ? "elements along x, y, z" : "elements along x, y");
    long long total = 1;
    for (long long k : body.elements) {
        total *= k;
    }
    if (total > 10'000'000) {
        t.fail("elements",
               fmt::format("expected at most 10 million elements per body, got {}", total));
    }
    return body;
}

fem::Mesh build_mesh(const std::vector<BodySpec>& bodies, int dimension) {
    fem::Mesh mesh;
    mesh.type = dimension == 2 ? fem::ElementType::quad4 : fem::ElementType::hex8;
    for (const BodySpec& b : bodies) {
        fem::Mesh part;
        if (dimension == 2) {
            fem::RectangleSpec r;
            r.width = b.size[0];
            r.height = b.size[1];
            r.nx = static_cast<int>(b.elements[0]);
            r.ny = static_cast<int>(b.elements[1]);
            r.origin = {b.origin[0], b.origin[1]};
            part = fem::rectangle_mesh(r);
        } else {
            fem::BoxSpec x;
            x.width = b.size[0];
            x.depth = b.size[1];
            x.height = b.size[2];
            x.nx = static_cast<int>(b.elements[0]);
            x.ny = static_cast<int>(b.elements[1]);
            x.nz = static_cast<int>(b.elements[2]);
            x.origin = {b.origin[0], b.origin[1], b.origin[2]};
            part = fem::box_mesh(x);
        }
        fem::append_body(mesh, part, b.name);
    }
    return mesh;
}

} // namespace ifsim::io
