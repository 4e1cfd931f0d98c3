#pragma once
// The [initial] table of an element test: the flat initial state of the chosen model
// (layout of kernels/model_api.hpp) with its defaults, checked for admissibility.
//
//   all models:      stress (kPa, 6 values), void_ratio
//   hypoplasticity:  intergranular_strain h (default 0), |h| <= R
//   sanisand:        back_stress alpha (default dev(sigma)/(tr(sigma)/3), the cone's axis),
//                    fabric z (default 0); alpha_in starts equal to alpha

#include <array>
#include <vector>

#include "io/scene/material_parameters.hpp"
#include "io/scene/table_reader.hpp"

namespace ifsim::io {

// Throws SceneError for a missing, malformed or inadmissible initial state.
std::vector<double> read_initial_state(const TableReader& initial, const MaterialSpec& material);

// The flat state of `material` for a given stress and void ratio, with the model state read from
// t's optional keys (intergranular_strain; back_stress, fabric) and their defaults as above.
// Checks admissibility and rejects keys of another model; the caller checks t's other keys.
// Error messages name t's keys "stress" and "void_ratio" for the stress and void ratio.
std::vector<double> model_state(const TableReader& t, const MaterialSpec& material,
                                const std::array<double, 6>& stress, double void_ratio);

} // namespace ifsim::io
