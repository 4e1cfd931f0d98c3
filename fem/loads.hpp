#pragma once
// Load vectors that scale with one factor: built once when a stage first asks for them, then
// multiplied by the ramped value (gravity g, pressure p) every increment. Full-length vectors
// over the DOFs (node * dim + direction), reference configuration (small strain).

#include <string>
#include <vector>

#include "fem/mesh.hpp"

namespace ifsim::fem {

// Nodal forces of gravity g = 1 m/s^2 along the negative vertical (last) axis:
// f_a = -int N_a rho dV e_vertical, rho per element (t/m^3, so rho g is kN/m^3).
// Integrated with the full Gauss rule whatever the stiffness integration.
std::vector<double> unit_gravity_forces(const Mesh& mesh, const std::vector<double>& density);

// Nodal forces of a unit normal pressure (1 kPa, compression: pushes into the body) on a face
// set: f_a = -int N_a n dA with n the outward normal (paper Eqs. A3, A4).
std::vector<double> unit_pressure_forces(const Mesh& mesh, const std::string& face_set);

} // namespace ifsim::fem
