#pragma once
// Built-in parameter sets of the paper (Staubach, Machacek, Wichtmann 2022), as plain data.
// Units: kPa, radians after conversion.

#include <numbers>
#include <optional>
#include <string_view>

#include "kernels/hypoplasticity.hpp"
#include "kernels/sanisand.hpp"

namespace ifsim::parameter_sets {

inline constexpr double deg = std::numbers::pi / 180.0;

// Table 1: crushed quartz sand "L4C".
inline HypoplasticityParams hypoplasticity_l4c() {
    HypoplasticityParams p;
    p.phi_c = 36.0 * deg;
    p.e_i0 = 1.320;
    p.e_c0 = 1.149;
    p.e_d0 = 0.763;
    p.h_s = 4.5e6;
    p.n = 0.28;
    p.alpha = 0.094;
    p.beta = 1.2;
    p.m_R = 2.4;
    p.m_T = 1.2;
    p.R = 1.0e-4;
    p.beta_R = 0.3;
    p.chi = 1.5;
    return p;
}

// Table 3: "Karlsruhe Sand".
inline HypoplasticityParams hypoplasticity_karlsruhe() {
    HypoplasticityParams p;
    p.phi_c = 33.1 * deg;
    p.e_i0 = 0.979;
    p.e_c0 = 0.851;
    p.e_d0 = 0.549;
    p.h_s = 19.0e6;
    p.n = 0.285;
    p.alpha = 0.1;
    p.beta = 0.32;
    p.m_R = 2.4;
    p.m_T = 1.2;
    p.R = 5.0e-5;
    p.beta_R = 0.08;
    p.chi = 7.0;
    return p;
}

inline std::optional<HypoplasticityParams> hypoplasticity(std::string_view name) {
    if (name == "l4c") {
        return hypoplasticity_l4c();
    }
    if (name == "karlsruhe-sand") {
        return hypoplasticity_karlsruhe();
    }
    return std::nullopt;
}

// Table 4: Sanisand for "Karlsruhe Sand" (c = 0.88 as listed; see SanisandParams::prepare for
// the jump of c against Eq. 33 at kappa = 1).
inline SanisandParams sanisand_karlsruhe() {
    SanisandParams p;
    p.p_a = 100.0;
    p.e0 = 1.1;
    p.lambda_c = 0.25;
    p.xi = 0.35;
    p.M_c = 1.3;
    p.c = 0.88;
    p.m = 0.05;
    p.G0 = 70.0;
    p.nu = 0.05;
    p.h0 = 8.0;
    p.c_h = 0.35;
    p.n_b = 1.3;
    p.A0 = 0.8;
    p.n_d = 0.8;
    p.z_max = 60.0;
    p.c_z = 2000.0;
    p.prepare();
    return p;
}

inline std::optional<SanisandParams> sanisand(std::string_view name) {
    if (name == "karlsruhe-sand") {
        return sanisand_karlsruhe();
    }
    return std::nullopt;
}

} // namespace ifsim::parameter_sets
