#pragma once
// Equation numbers of the displacement DOFs in one stage. Dirichlet conditions are eliminated
// (a prescribed DOF has no equation; its value is set before the Newton iteration); the nodes
// of an equal-displacement set share the equation of their master (the set's first node), so
// the reduced system is T^T K T with T the 0/1 master-slave map: exact, no penalty.
// DOF d = node * dim + direction.

#include <vector>

#include "fem/mesh.hpp"
#include "fem/stage.hpp"

namespace ifsim::fem {

struct DofMap {
    int dim = 2;
    int n_equations = 0;
    std::vector<int> equation;             // per DOF: equation, or -1 when prescribed
    std::vector<int> prescribed;           // prescribed DOFs, ascending
    std::vector<double> prescribed_change; // their change over the stage
    std::vector<int> master_of;            // per DOF: its master DOF (itself if none)

    int n_dofs() const { return static_cast<int>(equation.size()); }
};

// Throws std::invalid_argument for a direction outside the mesh dimension, a DOF prescribed
// twice with different changes, a prescribed DOF inside an equal-displacement set, or a DOF
// in two equal-displacement sets; the message names the node, direction and sets.
DofMap build_dof_map(const Mesh& mesh, const Stage& stage);

} // namespace ifsim::fem
