#pragma once
// The [mesh] table and the [[body]] blocks of a boundary-value scene: each body is a structured
// block (fem's rectangle_mesh or box_mesh), and the blocks are merged into one mesh without
// sharing nodes. A body's sets are renamed "<body>.<set>" (node and face sets left, right,
// bottom, top, front, back, and the node set "<body>.all"); its elements form the element set
// "<body>". Alternatively [mesh] names a Gmsh file (file = "path.msh", relative to the scene
// file's folder) whose physical groups are the sets (io/mesh/gmsh_reader.hpp); its [[region]]
// entries then give the materials (io/boundary_value/boundary_value_region.hpp).

#include <filesystem>
#include <string>
#include <vector>

#include "fem/element_geometry.hpp"
#include "fem/mesh.hpp"
#include "io/scene/table_reader.hpp"

namespace ifsim::io {

struct BodySpec {
    std::string name;
    std::string material;       // a key of [material]
    std::vector<double> origin; // lower corner, m
    std::vector<double> size;   // width, (depth,) height, m
    std::vector<long long> elements;
    double top() const { return origin.back() + size.back(); } // vertical coordinate
};

struct MeshSpec {
    int dimension = 2;
    std::string integration; // full | reduced
    fem::Integration rule = fem::Integration::full;
    std::string kinematics = "small-strain"; // small-strain | updated-lagrangian
    std::string file;                        // as written; empty for [[body]] blocks
    std::filesystem::path path;              // file resolved against the scene file's folder
};

// [mesh]. Throws SceneError.
MeshSpec read_mesh_spec(const TableReader& mesh);

// The mesh of spec.file. Throws SceneError on mesh.file naming the mesh file, its line and
// what was expected, or on mesh.dimension when the file's dimension differs.
fem::Mesh read_mesh_file(const TableReader& mesh, const MeshSpec& spec);

// One [[body]] entry; `materials` are the keys of [material]. Throws SceneError.
BodySpec read_body(const TableReader& body, int dimension,
                   const std::vector<std::string>& materials);

// The bodies' blocks merged into one mesh with the sets named as above.
fem::Mesh build_mesh(const std::vector<BodySpec>& bodies, int dimension);

} // namespace ifsim::io
