#pragma once
// Storage aligned and padded for the SIMD lanes.

#include <cstddef>
#include <vector>

#include <xsimd/xsimd.hpp>

#include "kernels/simd.hpp"

namespace ifsim {

using aligned_vector = std::vector<double, xsimd::aligned_allocator<double, 64>>;

// Smallest multiple of the lane width (and of a cache line of doubles) holding n entries.
inline std::size_t padded_size(std::size_t n) {
    const std::size_t w = simd::lanes > 8 ? simd::lanes : 8;
    return ((n + w - 1) / w) * w;
}

} // namespace ifsim
