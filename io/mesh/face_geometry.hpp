#pragma once
// Area and outward unit normal of the faces of a face set in the reference configuration
// (2D: edges per m of thickness; 3D: the bilinear face's area from its diagonals, exact for a
// plane face). Used to turn forces and stresses on a face set into mean tractions.

#include <array>
#include <string>

#include "fem/mesh.hpp"

namespace ifsim::io {

struct FaceGeometry {
    double area = 0.0;
    std::array<double, 3> normal{}; // outward unit normal
};

FaceGeometry face_geometry(const fem::Mesh& mesh, const fem::FaceRef& face);

// Total area and area-weighted mean outward normal (unit) of a face set.
FaceGeometry face_set_geometry(const fem::Mesh& mesh, const std::string& face_set);

} // namespace ifsim::io
