#pragma once
// The [[region]] entries of a boundary-value scene whose mesh comes from a file ([mesh] file):
//
//   set = "soil"          an element set of the mesh (a physical group of the file)
//   material = "sand"     a key of [material]
//
// Every element must get exactly one material: the regions' sets are disjoint and cover the
// mesh. Each region is returned as a BodySpec named after its set (the materials and the
// interface find the body's elements by that name) with the bounding box of its nodes as
// origin and size (the default K0 surface and the mid-height of the state's checks).

#include <string>
#include <vector>

#include "fem/mesh.hpp"
#include "io/boundary_value/boundary_value_mesh.hpp"
#include "io/scene/table_reader.hpp"

namespace ifsim::io {

// `root`: the scene's root table; `materials`: the keys of [material]. Throws SceneError.
std::vector<BodySpec> read_regions(const TableReader& root, const fem::Mesh& mesh,
                                   const std::vector<std::string>& materials);

} // namespace ifsim::io
