#pragma once
// Per-lane solution of k x k linear systems, k = 1, 2 or 3 (the same k in every lane), by the
// explicit inverse (cofactors). Used by Algorithm 1's Newton on the interface normal strains.
// A lane with a (nearly) singular matrix gets a zero correction and a false `solved` mask.

#include <array>

#include "kernels/simd.hpp"

namespace ifsim {

template <class T>
struct SmallSolve {
    std::array<T, 3> x{T(0.0), T(0.0), T(0.0)};
    simd::mask_t<T> solved{};
};

// Solves A x = b for the leading k x k block of A (row-major A[r][c]).
template <class T>
SmallSolve<T> small_solve(int k, const std::array<std::array<T, 3>, 3>& A,
                          const std::array<T, 3>& b) {
    SmallSolve<T> s;
    if (k == 1) {
        const T d = A[0][0];
        s.solved = simd::abs(d) > 1.0e-300;
        s.x[0] = simd::select(s.solved, b[0] / simd::select(s.solved, d, T(1.0)), T(0.0));
        return s;
    }
    if (k == 2) {
        const T det = A[0][0] * A[1][1] - A[0][1] * A[1][0];
        const T scale = simd::abs(A[0][0] * A[1][1]) + simd::abs(A[0][1] * A[1][0]);
        s.solved = simd::abs(det) > 1.0e-14 * scale;
        const T inv = 1.0 / simd::select(s.solved, det, T(1.0));
        s.x[0] = simd::select(s.solved, (A[1][1] * b[0] - A[0][1] * b[1]) * inv, T(0.0));
        s.x[1] = simd::select(s.solved, (A[0][0] * b[1] - A[1][0] * b[0]) * inv, T(0.0));
        return s;
    }
    // k == 3: adjugate / determinant.
    const T c00 = A[1][1] * A[2][2] - A[1][2] * A[2][1];
    const T c01 = A[1][2] * A[2][0] - A[1][0] * A[2][2];
    const T c02 = A[1][0] * A[2][1] - A[1][1] * A[2][0];
    const T det = A[0][0] * c00 + A[0][1] * c01 + A[0][2] * c02;
    T scale = T(0.0);
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) {
            scale = simd::max(scale, simd::abs(A[r][c]));
        }
    }
    s.solved = simd::abs(det) > 1.0e-13 * scale * scale * scale;
    const T inv = 1.0 / simd::select(s.solved, det, T(1.0));
    const T i00 = c00, i10 = c01, i20 = c02;
    const T i01 = A[0][2] * A[2][1] - A[0][1] * A[2][2];
    const T i11 = A[0][0] * A[2][2] - A[0][2] * A[2][0];
    const T i21 = A[0][1] * A[2][0] - A[0][0] * A[2][1];
    const T i02 = A[0][1] * A[1][2] - A[0][2] * A[1][1];
    const T i12 = A[0][2] * A[1][0] - A[0][0] * A[1][2];
    const T i22 = A[0][0] * A[1][1] - A[0][1] * A[1][0];
    s.x[0] = simd::select(s.solved, (i00 * b[0] + i01 * b[1] + i02 * b[2]) * inv, T(0.0));
    s.x[1] = simd::select(s.solved, (i10 * b[0] + i11 * b[1] + i12 * b[2]) * inv, T(0.0));
    s.x[2] = simd::select(s.solved, (i20 * b[0] + i21 * b[1] + i22 * b[2]) * inv, T(0.0));
    return s;
}

} // namespace ifsim
