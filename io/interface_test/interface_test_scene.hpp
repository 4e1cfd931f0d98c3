#pragma once
// A scene of kind "interface-test" (scene-format.md; paper §5) read into the engine's
// InterfaceTestSpec: the interface point (novel, Stutz or Coulomb), the soil sample in series
// with it, the normal control (CNL or CNS) and the stages of plate displacement, plus the
// optional [integration] settings. Every key is checked; keys that belong to another
// formulation, model or normal control are errors.

#include <string>

#include <toml++/toml.h>

#include "engine/interface_test_driver.hpp"
#include "io/interface_test/interface_initial_stress.hpp"
#include "io/scene/material_parameters.hpp"

namespace ifsim::io {

struct InterfaceTestScene {
    std::string description;
    std::string stutz_initial_stress; // continuum | normal-contact (stutz only)
    MaterialSpec interface_material;  // novel and stutz
    MaterialSpec sample_material;
    std::string normal_control;  // constant-stress | constant-stiffness
    double stiffness_given = 0.; // CNS: the scene's value in stiffness_unit
    std::string stiffness_unit;  // CNS: kPa/m | kPa/mm
    std::string subincrement;    // fixed | adaptive (novel, stutz)
    std::string jacobian;        // perturbation | full-perturbation | analytical (novel, stutz)
    InterfaceTestSpec spec;      // ready to run (normal_stiffness in kPa/m)

    bool coulomb() const {
        return spec.contact.interface.formulation == InterfaceFormulation::coulomb;
    }
    double initial_normal_stress() const { return spec.sample_state.at(0); } // t_N0
    long total_steps() const;
};

// Reads and checks the whole scene. Throws SceneError naming the file, the key and what was
// expected.
InterfaceTestScene read_interface_test_scene(const toml::table& scene, const std::string& file);

} // namespace ifsim::io
