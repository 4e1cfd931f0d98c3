#pragma once
// A Gmsh mesh file (ASCII MSH 4.1 or 2.2) as an fem::Mesh.
//
// The mesh dimension is the highest dimension of the file's elements: 2 -> quad4 (4-node
// quadrangles, Gmsh type 3; nodes must lie in z = 0, x and y are kept), 3 -> hex8 (8-node
// hexahedra, type 5). Another element type of that dimension is an error. Node tags may have
// gaps: the nodes of the elements are numbered densely in the order of their tags; elements
// keep the file's order. Each element is oriented (element_orientation.hpp): clockwise
// quadrangles and inverted hexahedra are mirrored, degenerate ones are errors.
//
// Physical groups become named sets; a group's name comes from $PhysicalNames, "group<tag>"
// when it has none, and must be unique among the groups used (and not "all"):
//  - of the mesh dimension: an element set and a node set (its elements' nodes);
//  - one dimension lower (2D: 2-node lines, type 1; 3D: 4-node quadrangles, type 3): a face
//    set, each boundary element matched to the one (element, local face) with its nodes (an
//    error when no element or two elements have them: face sets lie on the mesh boundary),
//    and a node set of their nodes;
//  - lower still (points; lines in 3D): a node set.
// Lower-dimensional elements in no physical group are ignored. The node set and the element
// set "all" hold everything.

#include <string>

#include "fem/mesh.hpp"
#include "io/mesh/gmsh_content.hpp"

namespace ifsim::io {

struct GmshMesh {
    fem::Mesh mesh;
    std::string version; // "4.1" | "2.2"
    int mirrored = 0;    // elements whose node order was mirrored
};

// Throws MeshFileError naming the file, the line and what was expected.
GmshMesh read_gmsh_mesh(const std::string& path);

// The mesh of parsed content. Throws MeshFileError.
GmshMesh build_gmsh_mesh(const GmshContent& content);

} // namespace ifsim::io
