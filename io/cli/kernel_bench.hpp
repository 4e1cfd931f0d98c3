#pragma once
// `ifsim kernel-bench`: times repeated batched constitutive updates of N valid, varied
// material points (engine/sample_states.hpp: K0-like stresses at 20-400 kPa with some shear,
// admissible void ratios, varied model state, increments of norm 1e-4 in varied directions).
//
// The trial state is never committed: every repetition integrates the same committed states
// with the same increments, so the states stay valid however long the benchmark runs and
// every repetition does the same work. One untimed warm-up repetition comes first; a model
// that carries its substep size between increments (hypoplasticity) then keeps the size the
// warm-up ended with, as in a run of equal increments (--cold: it starts without one).

#include <string>

#include <nlohmann/json.hpp>

#include "engine/model_registry.hpp"

namespace ifsim::io {

struct KernelBenchOptions {
    std::string model;                         // hypoplasticity | sanisand | linear-elastic
    std::string parameters = "karlsruhe-sand"; // built-in set (not used by linear-elastic)
    std::string formulation = "none";          // none | novel | stutz | coulomb
    double roughness = 1.0;
    long points = 0;
    int threads = 0; // 0 = all cores
    bool scalar = false;
    double seconds = 1.0;
    double strain_increment = 1.0e-4;
    std::string scheme = "rkf23"; // rkf23 | heun (kernels/explicit_integration.hpp)
    double tolerance = 1.0e-3;    // relative local error of one substep
    bool cold = false;            // no carried substep size in the timed repetitions
    bool no_split = false;        // h integrated with the stress (IntegrationSettings)
    bool implicit = false;        // Sanisand: backward-Euler steps (kernels/sanisand_implicit.hpp)
    // Interface formulations (interface_kernel_bench.hpp):
    std::string jacobian = "perturbation"; // perturbation | full-perturbation | analytical
    std::string subincrement = "fixed";    // fixed | adaptive
    double gap_increment = 3.0e-6;         // typical |dg_T| per update (m)
    double shear_band_thickness = 0.003;   // d_s0 (m)
};

// The benchmark's JSON object (an interface formulation runs interface_kernel_bench.hpp's).
// Throws std::invalid_argument for bad options.
nlohmann::ordered_json run_kernel_bench(const KernelBenchOptions& options);

// The continuum model of --model with --parameters and --roughness, prepared. Throws
// std::invalid_argument for an unknown model or set.
MaterialChoice kernel_bench_material(const KernelBenchOptions& options);

} // namespace ifsim::io
