#pragma once
// A [material.NAME] table of a boundary-value scene turned into the solver's material of one
// body (element set "<body>"): model and parameters as in the element test's [material], the
// density for gravity, and the initial state in GLOBAL axes (vertical = y in 2D, z in 3D):
//
//   stress = [6 values]                  uniform initial stress, or
//   k0, surcharge, unit_weight, surface  geostatic: sigma_v = -(surcharge + unit_weight
//                                        (surface - z)), sigma_h = k0 sigma_v (fem's K0Stress);
//                                        surface defaults to the top of the body
//   void_ratio                           required for hypoplasticity and sanisand
//   intergranular_strain | back_stress, fabric   the model's state keys (model_state)
//
// linear-elastic may leave out stress (zero) and void_ratio (1, only carried along).

#include <string>

#include "fem/solver_settings.hpp"
#include "io/boundary_value/boundary_value_mesh.hpp"
#include "io/scene/material_parameters.hpp"
#include "io/scene/table_reader.hpp"

namespace ifsim::io {

struct BodyMaterial {
    MaterialSpec spec;
    fem::ElementSetMaterial set;    // element_set = the body's name
    bool geostatic = false;         // K0 stress instead of a uniform one
    std::array<double, 6> stress{}; // uniform stress, or the K0 stress at mid-height
    double void_ratio = 0.0;
};

// Reads and checks the material table for `body` (its name and vertical extent); the state is
// checked with the stress at the body's mid-height. Throws SceneError.
BodyMaterial read_body_material(const TableReader& material, const BodySpec& body);

} // namespace ifsim::io
