#pragma once
// Integration-point data of every element, computed once per mesh (small strain: the
// reference geometry does not change): physical shape-function gradients, integration weights
// times det J, point coordinates, and for reduced integration the hourglass base vectors.
//
// Reduced integration uses the uniform-gradient element of Flanagan & Belytschko (1981): one
// point whose gradients are the volume averages bbar = (1/V) int grad N dV (2x2(x2) Gauss, exact)
// and whose weight is the exact volume V. In 2D bbar equals the centre gradients; in 3D the
// averaging keeps the patch test exact on distorted hexahedra.

#include <vector>

#include "fem/mesh.hpp"

namespace ifsim::fem {

enum class Integration { full, reduced };

struct ElementGeometry {
    int dim = 2;
    int nen = 4;
    int nip = 4; // integration points per element
    Integration integration = Integration::full;
    std::vector<double> dNdx;           // ((e * nip + q) * nen + a) * dim + i
    std::vector<double> dV;             // e * nip + q
    std::vector<double> ip_coordinates; // (e * nip + q) * dim + i
    std::vector<double> volume;         // per element (area for quad4: unit thickness)
    // Reduced integration only:
    int n_hourglass = 0;
    std::vector<double> hourglass_gamma; // (e * n_hourglass + alpha) * nen + a
    std::vector<double> hourglass_scale; // per element: V * sum_a,i bbar_a,i^2

    const double* gradients(int e, int q) const {
        return dNdx.data() + static_cast<std::size_t>((e * nip + q) * nen * dim);
    }
    double weight(int e, int q) const { return dV[static_cast<std::size_t>(e * nip + q)]; }
};

// Throws std::invalid_argument naming the element when det J <= 0 at a Gauss point. With a
// displacement vector (full DOF length) the geometry of the configuration X + u (updated
// Lagrangian).
ElementGeometry build_geometry(const Mesh& mesh, Integration integration,
                               const double* displacement = nullptr);

// Nodal coordinates of one element, node-major (plus the displacements when given).
void gather_coordinates(const Mesh& mesh, int element, double* X,
                        const double* displacement = nullptr);

} // namespace ifsim::fem
