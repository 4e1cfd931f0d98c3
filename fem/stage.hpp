#pragma once
// What a stage of a static analysis prescribes: constraints, loads and their ramps. A stage
// runs in `steps` equal increments of pseudo-time 0..1; every ramp is linear in it.
// Directions are 0 = x, 1 = y, 2 = z; the vertical axis is the last one.

#include <optional>
#include <string>
#include <vector>

namespace ifsim::fem {

// u = u(stage start) + change * t on every node of the set (change 0: fixed).
struct PrescribedDisplacement {
    std::string node_set;
    int direction = 0;
    double change = 0.0; // m over the stage
};

// All nodes of the set move by the same increment in one direction (a rigid plate). Enforced
// by elimination: the first node of the set is the master, the others share its equation.
struct EqualDisplacement {
    std::string node_set;
    int direction = 0;
};

// Linear springs to ground (constant normal stiffness): force -k (u - u_ref) on each node of
// the set, k = total_stiffness / number of nodes; u_ref is the displacement at the start of the
// first of the consecutive stages that name this spring (same set and direction).
struct GroundSpring {
    std::string node_set;
    int direction = 0;
    double total_stiffness = 0.0; // kN/m (per m of thickness in 2D)
};

// Uniform normal pressure on a face set, positive in compression (pushes into the body),
// ramped from `from` to `to` over the stage; consistent nodal forces on the reference faces.
struct FacePressure {
    std::string face_set;
    double from = 0.0; // kPa
    double to = 0.0;
};

// Gravity g along the negative vertical axis, ramped over the stage; body force rho g.
struct GravityRamp {
    double from = 0.0; // m/s^2
    double to = 0.0;
};

struct Stage {
    std::string name;
    int steps = 1;
    std::vector<PrescribedDisplacement> displacements;
    std::vector<EqualDisplacement> equal_displacements;
    std::vector<GroundSpring> springs;
    std::vector<FacePressure> pressures;
    std::optional<GravityRamp> gravity; // absent: no gravity in this stage
};

} // namespace ifsim::fem
