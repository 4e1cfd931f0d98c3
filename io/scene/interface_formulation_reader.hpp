#pragma once
// The formulation keys of an [interface] table, shared by the interface-test scene and the
// contact pair of a boundary-value scene (docs/scenes.md): the formulation (novel | stutz |
// coulomb), for the continuum formulations the interface model with roughness kappa, shear
// band thickness, Algorithm 1 sub-increments, tolerance and Jacobian, for Coulomb the friction
// coefficient and tangential stiffness. Keys of the other formulation are errors.
//
// The caller checks the table's other keys (allow_only) and builds the interface state from the
// optional state keys void_ratio, intergranular_strain, back_stress, fabric (model_state), which
// are rejected here for Coulomb friction.

#include <string>

#include "engine/contact_update.hpp"
#include "io/interface_test/interface_initial_stress.hpp"
#include "io/scene/material_parameters.hpp"
#include "io/scene/table_reader.hpp"
#include "kernels/coulomb.hpp"

namespace ifsim::io {

struct InterfaceFormulationSpec {
    InterfaceFormulation formulation = InterfaceFormulation::novel;
    std::string stutz_initial_stress; // stutz only: continuum | normal-contact
    MaterialSpec material;            // novel and stutz: the interface model
    std::string subincrement;         // fixed | adaptive (novel, stutz)
    std::string jacobian;             // perturbation | full-perturbation | analytical
    InterfaceStressStart stress_start = InterfaceStressStart::continuum;
    ContactOptions contact; // novel and stutz (interface.ndim left at its default)
    CoulombParams coulomb;  // coulomb

    bool is_coulomb() const { return formulation == InterfaceFormulation::coulomb; }
    std::string name() const;
};

// The scene names of the formulations: "novel", "stutz", "coulomb".
std::string_view formulation_name(InterfaceFormulation f);

// Throws SceneError naming the file and key.
InterfaceFormulationSpec read_interface_formulation(const TableReader& t);

// Why a key that tunes Algorithm 1 (the inner solves of the continuum formulations) is an error
// with Coulomb friction: the interface test's [integration] and a boundary-value pair alike.
inline const std::string algorithm1_key_with_coulomb =
    "tunes Algorithm 1 of the continuum formulations \"novel\" and \"stutz\"; expected no "
    "such key for formulation \"coulomb\"";

} // namespace ifsim::io
