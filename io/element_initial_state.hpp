#pragma once
// The [initial] table of an element test: the flat initial state of the chosen model
// (layout of kernels/model_api.hpp) with its defaults, checked for admissibility.
//
//   all models:      stress (kPa, 6 values), void_ratio
//   hypoplasticity:  intergranular_strain h (default 0), |h| <= R
//   sanisand:        back_stress alpha (default dev(sigma)/(tr(sigma)/3), the cone's axis),
//                    fabric z (default 0); alpha_in starts equal to alpha

#include <vector>

#include "io/material_parameters.hpp"
#include "io/table_reader.hpp"

namespace ifsim::io {

// Throws SceneError for a missing, malformed or inadmissible initial state.
std::vector<double> read_initial_state(const TableReader& initial, const MaterialSpec& material);

} // namespace ifsim::io
