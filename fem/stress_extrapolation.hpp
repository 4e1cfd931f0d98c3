#pragma once
// Extrapolation of the continuum stress of an element's integration points to a point of
// its surface (paper Eq. 14) and rotation into the local contact frame (Eqs. 15, 16).
// Stresses are Voigt 11 22 33 12 13 23 with tensor shear components.
//
// Full integration (2x2 / 2x2x2 Gauss at +-1/sqrt(3)): the integration points are the nodes
// of a "Gauss-point element" with stretched coordinates xi' = sqrt(3) xi, so the stress at
// natural coordinates xi is sum_q N_q(sqrt(3) xi) sigma_q with the bilinear/trilinear N_q —
// the inverse of interpolating nodal values to the Gauss points; exact for any field that is
// linear in the natural coordinates. Reduced (1 point): the constant point stress.

#include <array>
#include <span>
#include <vector>

#include "fem/mesh.hpp"

namespace ifsim::fem {

using Voigt6 = std::array<double, 6>;

// Stress at natural coordinates xi (dim entries) of an element whose integration-point
// stresses are given in the order of gauss_rule<dim>() (bit i of the point index = sign of
// xi_i); point_stress.size() is 1 (reduced) or 2^dim (full). Throws otherwise.
Voigt6 extrapolate_stress(int dim, std::span<const Voigt6> point_stress, const double* xi);

// Natural coordinates of the point at edge coordinate s in [-1, 1] of local face f of a
// quad4 (linear between the face's nodes, as the element map is along the edge).
std::array<double, 2> quad4_face_point(int local_face, double s);

// Mean of the extrapolations from several adjacent elements (a point between elements).
Voigt6 average_stress(std::span<const Voigt6> extrapolated);

// Eq. 15: sigma' = alpha sigma alpha^T with alpha_ij = e'_i . e_j (Eq. 16); the rows of the
// local frame are e'_1 = n, e'_2 = t1, e'_3 = t2 (global components, orthonormal).
Voigt6 rotate_to_frame(const Voigt6& s, const std::array<double, 3>& n,
                       const std::array<double, 3>& t1, const std::array<double, 3>& t2);

} // namespace ifsim::fem
