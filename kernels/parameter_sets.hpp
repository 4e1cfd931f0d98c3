#pragma once
// Built-in parameter sets of the paper (Staubach, Machacek, Wichtmann 2022), as plain data.
// Units: kPa, radians after conversion.

#include <numbers>
#include <optional>
#include <string_view>

#include "kernels/hypoplasticity.hpp"

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

} // namespace ifsim::parameter_sets
