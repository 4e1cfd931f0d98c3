#pragma once
// Shared by the Sanisand kernel suites: state types for the scalar and SIMD paths and the
// Karlsruhe sand set (Table 4) at a chosen roughness factor.

#include <array>
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

// One state or strain increment per SIMD lane.
inline YB pack_states(const std::array<Y, W>& ys) {
    YB yb;
    for (int k = 0; k < Sanisand::n_state; ++k) {
        alignas(64) double buf[W];
        for (std::size_t l = 0; l < W; ++l) {
            buf[l] = ys[l][k];
        }
        yb[k] = Batch::load_aligned(buf);
    }
    return yb;
}
inline Sym<Batch> pack_increments(const std::array<Sym<double>, W>& ds) {
    Sym<Batch> db;
    for (int k = 0; k < 6; ++k) {
        alignas(64) double buf[W];
        for (std::size_t l = 0; l < W; ++l) {
            buf[l] = ds[l][k];
        }
        db[k] = Batch::load_aligned(buf);
    }
    return db;
}

} // namespace ifsim::sanisand_test
