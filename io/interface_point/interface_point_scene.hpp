#pragma once
// The scene kind "interface-point": one call of Algorithm 1 for one contact point, with its
// state and inputs given in full. A failed run writes one as its replay.toml (io/replay/), so
// the failed call can be run again alone; one can also be written by hand to probe a point.
//
//   [interface]   formulation ("novel" | "stutz"), model, parameters, roughness
//   [algorithm1]  every option of the call (io/interface_point/algorithm1_options.hpp)
//   [point]       ndim (2 | 3), model_state (the interface model's flat state in local axes),
//                 normal_strain, in_plane_strain [eps_p1, eps_p2], shear_strain [gamma1,
//                 gamma2], last_subincrement
//   [increment]   normal_traction t_N, penalty k_N, slip_increment [dg1, dg2],
//                 in_plane_stress [s_p1, s_p2] (novel), in_plane_stress_slope (d s_p / d t_N),
//                 normal, tangent1, tangent2 (the local frame in global axes)

#include <string>

#include <toml++/toml.h>

#include "engine/failed_contact_point.hpp"
#include "io/scene/material_parameters.hpp"

namespace ifsim::io {

struct InterfacePointScene {
    std::string description;
    MaterialSpec material;    // the interface model (roughness applied)
    FailedContactPoint point; // state, inputs, options and ndim of the call
};

// Throws SceneError naming the file and key.
InterfacePointScene read_interface_point_scene(const toml::table& table, const std::string& file);

// The [point] and [increment] tables of a call (shared with the replay writer).
toml::table point_table(const FailedContactPoint& point, int model_state_size);
toml::table increment_table(const FailedContactPoint& point);

} // namespace ifsim::io
