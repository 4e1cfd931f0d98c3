#pragma once
// Structured meshes of a rectangle (quad4) or a box (hex8) with named boundary sets.
//
// The vertical axis is the last one (y in 2D, z in 3D): gravity and depth refer to it.
// Node and face sets: left/right (x = min/max), bottom/top (vertical min/max) and, in 3D,
// front/back (y = min/max). Element set "all"; node set "all".

#include <array>
#include <string>

#include "fem/mesh.hpp"

namespace ifsim::fem {

struct RectangleSpec {
    double width = 1.0;  // along x
    double height = 1.0; // along y (vertical)
    int nx = 1;
    int ny = 1;
    std::array<double, 2> origin{0.0, 0.0};
};

struct BoxSpec {
    double width = 1.0;  // along x
    double depth = 1.0;  // along y
    double height = 1.0; // along z (vertical)
    int nx = 1;
    int ny = 1;
    int nz = 1;
    std::array<double, 3> origin{0.0, 0.0, 0.0};
};

// Throw std::invalid_argument for non-positive sizes or element counts.
Mesh rectangle_mesh(const RectangleSpec& spec);
Mesh box_mesh(const BoxSpec& spec);

// Appends `body` to `into` as a separate body (no shared nodes): its sets are renamed
// "<name>.<set>" and its elements form the element set "<name>". Throws std::invalid_argument
// for another element type or a name already used.
void append_body(Mesh& into, const Mesh& body, const std::string& name);

} // namespace ifsim::fem
