#pragma once
// `ifsim kernel-bench`: times repeated batched constitutive updates of N valid, varied
// material points (engine/sample_states.hpp: K0-like stresses at 20-400 kPa with some shear,
// admissible void ratios, varied model state, increments of norm 1e-4 in varied directions).
//
// The trial state is never committed: every repetition integrates the same committed states
// with the same increments, so the states stay valid however long the benchmark runs and
// every repetition does the same work. One untimed warm-up repetition comes first.

#include <string>

#include <nlohmann/json.hpp>

namespace ifsim::io {

struct KernelBenchOptions {
    std::string model;                         // hypoplasticity | sanisand | linear-elastic
    std::string parameters = "karlsruhe-sand"; // built-in set (not used by linear-elastic)
    std::string formulation = "none";          // interface formulation: none only, for now
    double roughness = 1.0;
    long points = 0;
    int threads = 0; // 0 = all cores
    bool scalar = false;
    double seconds = 1.0;
    double strain_increment = 1.0e-4;
};

// The benchmark's JSON object. Throws std::invalid_argument for bad options.
nlohmann::ordered_json run_kernel_bench(const KernelBenchOptions& options);

} // namespace ifsim::io
