#pragma once
// Symmetric second-order tensors in Voigt order 11, 22, 33, 12, 13, 23 with TENSOR shear
// components (not engineering gamma). Written once over the value type T.

#include <array>

#include "kernels/simd.hpp"

namespace ifsim {

template <class T>
using Sym = std::array<T, 6>;

namespace voigt {

template <class T>
inline Sym<T> zero() {
    return {T(0.0), T(0.0), T(0.0), T(0.0), T(0.0), T(0.0)};
}
template <class T>
inline Sym<T> identity() {
    return {T(1.0), T(1.0), T(1.0), T(0.0), T(0.0), T(0.0)};
}
template <class T>
inline T trace(const Sym<T>& a) {
    return a[0] + a[1] + a[2];
}
// Double contraction A : B (shear components count twice).
template <class T>
inline T ddot(const Sym<T>& a, const Sym<T>& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] +
           2.0 * (a[3] * b[3] + a[4] * b[4] + a[5] * b[5]);
}
template <class T>
inline T norm(const Sym<T>& a) {
    return simd::sqrt(ddot(a, a));
}
template <class T>
inline Sym<T> scale(const Sym<T>& a, const T& s) {
    return {a[0] * s, a[1] * s, a[2] * s, a[3] * s, a[4] * s, a[5] * s};
}
template <class T>
inline Sym<T> add(const Sym<T>& a, const Sym<T>& b) {
    return {a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3], a[4] + b[4], a[5] + b[5]};
}
template <class T>
inline Sym<T> sub(const Sym<T>& a, const Sym<T>& b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2], a[3] - b[3], a[4] - b[4], a[5] - b[5]};
}
// a + s * b
template <class T>
inline Sym<T> axpy(const Sym<T>& a, const T& s, const Sym<T>& b) {
    return {a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2],
            a[3] + s * b[3], a[4] + s * b[4], a[5] + s * b[5]};
}
template <class T>
inline Sym<T> deviator(const Sym<T>& a) {
    const T m = trace(a) * (1.0 / 3.0);
    return {a[0] - m, a[1] - m, a[2] - m, a[3], a[4], a[5]};
}
// Matrix product A.A of a symmetric tensor (symmetric again).
template <class T>
inline Sym<T> square(const Sym<T>& a) {
    return {a[0] * a[0] + a[3] * a[3] + a[4] * a[4], a[3] * a[3] + a[1] * a[1] + a[5] * a[5],
            a[4] * a[4] + a[5] * a[5] + a[2] * a[2], a[0] * a[3] + a[3] * a[1] + a[4] * a[5],
            a[0] * a[4] + a[3] * a[5] + a[4] * a[2], a[3] * a[4] + a[1] * a[5] + a[5] * a[2]};
}
// tr(A.A.A)
template <class T>
inline T trace_cube(const Sym<T>& a) {
    return ddot(square(a), a);
}
template <class T>
inline Sym<T> select(const simd::mask_t<T>& m, const Sym<T>& a, const Sym<T>& b) {
    Sym<T> r;
    for (int i = 0; i < 6; ++i) {
        r[i] = simd::select(m, a[i], b[i]);
    }
    return r;
}
template <class T>
inline simd::mask_t<T> all_finite(const Sym<T>& a) {
    auto m = simd::isfinite(a[0]);
    for (int i = 1; i < 6; ++i) {
        m = m && simd::isfinite(a[i]);
    }
    return m;
}

} // namespace voigt
} // namespace ifsim
