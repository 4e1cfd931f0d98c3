#pragma once
// The [material] table of a scene: model, parameters (a built-in set by name or an inline
// table with every value of the model) and roughness kappa, turned into the engine's
// MaterialChoice with prepare() called.
//
// Inline parameter names follow the paper's symbols:
//   hypoplasticity: phi_c (degrees), h_s (kPa), n, e_i0, e_c0, e_d0, alpha, beta,
//                   m_R, m_T, R, beta_R, chi
//   sanisand:       p_a (kPa), e0, lambda_c, xi, M_c, c, m, G0, nu, h0, c_h, n_b, A0, n_d,
//                   z_max, c_z
//   linear-elastic: E (kPa), nu

#include <initializer_list>
#include <string>
#include <string_view>

#include "engine/model_registry.hpp"
#include "io/scene/table_reader.hpp"

namespace ifsim::io {

struct MaterialSpec {
    MaterialChoice choice;
    std::string model;             // hypoplasticity | sanisand | linear-elastic
    std::string parameters;        // name of the built-in set, or "inline"
    double roughness = 1.0;        // kappa (hypoplasticity and sanisand)
    toml::table inline_parameters; // the scene's table when parameters = "inline" (for replays)
};

// Reads and checks [material]. Throws SceneError.
MaterialSpec read_material(const TableReader& material);

// The keys `model` and `parameters` of a table that describes a material among other things
// (an interface-test's [interface] or [sample]); the caller checks the table's other keys.
// A missing `model` takes `default_model`, a missing `parameters` the model's default set
// (`l4c` for hypoplasticity, the paper's Table 1 of §5; `karlsruhe-sand` for sanisand);
// with an empty default_model the key is required. The accepted models are those of
// engine/model_registry.hpp, or only those usable as interface models. Throws SceneError.
MaterialSpec read_model_and_parameters(const TableReader& table, std::string_view default_model,
                                       bool only_interface_models, double roughness);

} // namespace ifsim::io
