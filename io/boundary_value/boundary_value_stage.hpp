#pragma once
// One [[stage]] of a boundary-value scene as fem's Stage (docs/scenes.md):
//
//   name, steps
//   displacement = [{ nodes, direction, change = 0 }]   prescribed, ramped (0: fixed)
//   equal        = [{ nodes, direction }]               equal increments (rigid plate tie)
//   pressure     = [{ faces, from, to = from }]         kPa, compression positive
//   spring       = [{ faces, direction, stiffness, stiffness_unit = "kPa/m" }]
//                  springs to ground on the faces' nodes; total = stiffness x face-set area
//   gravity      = { from, to = from }                  m/s^2
//
// Directions are "x", "y" and, in 3D, "z" (the vertical axis is the last). Sets are checked
// against the mesh, and the stage's constraints against each other (fem's DOF map).

#include "fem/mesh.hpp"
#include "fem/stage.hpp"
#include "io/scene/table_reader.hpp"

namespace ifsim::io {

// `mesh` gains a node set "<faces>#nodes" for each spring's faces. Throws SceneError.
fem::Stage read_boundary_value_stage(const TableReader& stage, fem::Mesh& mesh, int number);

} // namespace ifsim::io
