#pragma once
// The contact pairs of a boundary-value scene: either the one [interface] table (the pair named
// "interface") or an array [[contact]] of pairs, each with
//
//   name               required, unique among the pairs, [A-Za-z0-9_-]+
//
// and every key of [interface] with the same meaning and defaults (read_boundary_value_pair).
// A scene has one or the other, not both; without either it has no contact.

#include <map>
#include <string>
#include <vector>

#include "fem/mesh.hpp"
#include "io/boundary_value/boundary_value_interface.hpp"
#include "io/boundary_value/boundary_value_material.hpp"
#include "io/scene/table_reader.hpp"

namespace ifsim::io {

// The pairs in the scene's order (the solver's order). Throws SceneError.
std::vector<BoundaryValueInterface>
read_boundary_value_contacts(const TableReader& root, const fem::Mesh& mesh,
                             const std::map<std::string, BodyMaterial>& materials);

} // namespace ifsim::io
