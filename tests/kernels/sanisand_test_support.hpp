#pragma once
// Shared by the Sanisand kernel suites: state types for the scalar and SIMD paths and the
// Karlsruhe sand set (Table 4) at a chosen roughness factor.

#include <cstddef>

#include "kernels/parameter_sets.hpp"
#include "kernels/sanisand.hpp"

namespace ifsim::sanisand_test {

using Y = Sanisand::State<double>;
using Batch = simd::batch;
using YB = Sanisand::State<Batch>;
constexpr std::size_t W = simd::lanes;

inline SanisandParams karlsruhe(double kappa = 1.0) {
    SanisandParams p = parameter_sets::sanisand_karlsruhe();
    p.roughness = kappa;
    p.prepare();
    return p;
}

} // namespace ifsim::sanisand_test
