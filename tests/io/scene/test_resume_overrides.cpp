// Which --set keys a resumed run may change: how the equations are solved, never what they are.

#include <string>

#include <gtest/gtest.h>

#include "io/scene/resume_overrides.hpp"

namespace ifsim::io {
namespace {

TEST(ResumeOverrides, SolutionControlsMayChange) {
    EXPECT_EQ(resume_override_refusal("solver.gather_relaxation=\"aitken\""), "");
    EXPECT_EQ(resume_override_refusal("solver.check_tangent = true"), "");
    EXPECT_EQ(resume_override_refusal("contact.1.jacobian=\"central\""), "");
    EXPECT_EQ(resume_override_refusal("contact.12.jacobian_tolerance=1e-9"), "");
    EXPECT_EQ(resume_override_refusal("interface.slip_viscosity=500"), "");
    for (const std::string_view key : resumable_contact_keys()) {
        EXPECT_EQ(resume_override_refusal("contact.2." + std::string(key) + "=1"), "") << key;
    }
}

TEST(ResumeOverrides, WhatTheStateWasMadeWithMayNot) {
    for (const char* set :
         {"contact.1.model=\"sanisand\"", "contact.1.formulation=\"stutz\"",
          "contact.1.shear_band_thickness=0.004", "contact.1.open_threshold=0.1",
          "interface.roughness=0.5", "mesh.file=\"other.msh\"", "material.sand.void_ratio=0.7",
          "stage.2.steps=10", "contact.x.jacobian=\"central\"", "contact.jacobian=\"central\"",
          "solver.=1", "solver"}) {
        const std::string why = resume_override_refusal(set);
        EXPECT_NE(why, "") << set;
    }
    const std::string why = resume_override_refusal("contact.1.model=\"sanisand\"");
    EXPECT_NE(why.find("contact.1.model"), std::string::npos) << why; // names the key
    EXPECT_NE(why.find("solver."), std::string::npos) << why;         // and what may change
}

} // namespace
} // namespace ifsim::io
