#pragma once
// `ifsim kernel-bench --formulation novel|stutz|coulomb`: times repeated batched contact-point
// updates of N valid, varied interface points.
//
//   novel, stutz  the contact engine (engine/contact_update.hpp): per point Algorithm 1 for the
//                 base lane and, for the perturbation Jacobians, its 2 ndim perturbed lanes
//                 (Eq. 37; ndim = 3). Model state from engine/sample_states.hpp in local axes
//                 (in-plane shear of Eq. 17 zeroed), t_N = s11, s_p1 = s22, s_p2 = s33, so
//                 every point starts in equilibrium; tangential gap increments of a few
//                 micrometres in varied directions; d_s0 = 3 mm; varied local frames.
//   coulomb       the batched Coulomb update (engine/coulomb_contact.hpp) with its analytical
//                 Jacobian: t_N from 20 to 400 kPa, shear tractions inside the friction cone,
//                 the same gap increments.
// The trial state is never committed: every repetition does the same work from the same valid
// states. One untimed warm-up repetition comes first.

#include <nlohmann/json.hpp>

#include "io/cli/kernel_bench.hpp"

namespace ifsim::io {

// The benchmark's JSON object. Throws std::invalid_argument for bad options.
nlohmann::ordered_json run_interface_kernel_bench(const KernelBenchOptions& options);

} // namespace ifsim::io
