#pragma once
// The node order of a quad4 or hex8 read from a mesh file, checked against fem's local order
// (fem/mesh.hpp): the Jacobian of the isoparametric map must be positive. An element whose
// Jacobian at the centre is negative is mirrored (quad4: clockwise -> counter-clockwise by
// reversing the nodes after the first; hex8: its zeta = -1 and zeta = +1 faces swapped). The
// Jacobian must then be positive at the centre and at every node, or the element is degenerate
// or too distorted (a non-convex quadrangle, a twisted hexahedron).

#include <span>
#include <vector>

#include "fem/mesh.hpp"

namespace ifsim::io {

enum class Orientation { kept, mirrored, invalid };

// `nodes`: the element's node indices into `coordinates` (dimension values per node), reordered
// in place when mirrored.
Orientation orient_element(fem::ElementType type, std::span<int> nodes,
                           const std::vector<double>& coordinates);

} // namespace ifsim::io
