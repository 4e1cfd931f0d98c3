#pragma once
// Per-lane solution of an N x N linear system by Gaussian elimination with partial pivoting,
// written once over the value type (each SIMD lane pivots on its own rows). Used by the
// backward-Euler step of Sanisand (kernels/sanisand_implicit.hpp). A lane whose pivot falls
// below `singular_ratio` times the largest entry of its matrix gets a false `solved` mask and
// a zero solution.

#include <array>

#include "kernels/simd.hpp"

namespace ifsim {

template <class T, int N>
using DenseMatrix = std::array<std::array<T, N>, N>;
template <class T, int N>
using DenseVector = std::array<T, N>;

// Solves A x = b in place: A is destroyed, b becomes x. Returns the lanes that were solved.
template <class T, int N>
simd::mask_t<T> dense_solve(DenseMatrix<T, N>& A, DenseVector<T, N>& b,
                            double singular_ratio = 1.0e-14) {
    T largest(0.0);
    for (int r = 0; r < N; ++r) {
        for (int c = 0; c < N; ++c) {
            largest = simd::max(largest, simd::abs(A[r][c]));
        }
    }
    const T floor = singular_ratio * largest;
    simd::mask_t<T> solved = largest > 0.0;
    for (int k = 0; k < N; ++k) {
        // the pivot row of each lane
        T best = simd::abs(A[k][k]);
        T at(static_cast<double>(k));
        for (int r = k + 1; r < N; ++r) {
            const T v = simd::abs(A[r][k]);
            const auto better = v > best;
            best = simd::select(better, v, best);
            at = simd::select(better, T(static_cast<double>(r)), at);
        }
        solved = solved && (best > floor);
        // swap row k with the pivot row, lane by lane
        for (int r = k + 1; r < N; ++r) {
            const auto m = at == T(static_cast<double>(r));
            if (simd::none(m)) {
                continue;
            }
            for (int c = k; c < N; ++c) {
                const T a = A[k][c];
                A[k][c] = simd::select(m, A[r][c], a);
                A[r][c] = simd::select(m, a, A[r][c]);
            }
            const T v = b[k];
            b[k] = simd::select(m, b[r], v);
            b[r] = simd::select(m, v, b[r]);
        }
        const T inv = 1.0 / simd::select(best > floor, A[k][k], T(1.0));
        for (int r = k + 1; r < N; ++r) {
            const T l = A[r][k] * inv;
            for (int c = k + 1; c < N; ++c) {
                A[r][c] -= l * A[k][c];
            }
            b[r] -= l * b[k];
        }
    }
    for (int k = N - 1; k >= 0; --k) {
        T v = b[k];
        for (int c = k + 1; c < N; ++c) {
            v -= A[k][c] * b[c];
        }
        b[k] = v / simd::select(solved, A[k][k], T(1.0));
    }
    for (int k = 0; k < N; ++k) {
        b[k] = simd::select(solved, b[k], T(0.0));
    }
    return solved;
}

} // namespace ifsim
