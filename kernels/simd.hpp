#pragma once
// One vocabulary for kernels written once over the value type: T = double (scalar reference
// path) or T = xsimd::batch<double> (the SIMD path, one lane per point). Kernels call only the
// functions below, so the same source compiles for both.

#include <cmath>
#include <cstddef>

#include <xsimd/xsimd.hpp>

namespace ifsim::simd {

using batch = xsimd::batch<double>;
using batch_mask = xsimd::batch_bool<double>;

// Lane width of the SIMD path, fixed by the build's instruction set (xsimd default arch).
inline constexpr std::size_t lanes = batch::size;

template <class T>
struct value_traits;

template <>
struct value_traits<double> {
    using mask = bool;
    static constexpr std::size_t width = 1;
};

template <>
struct value_traits<batch> {
    using mask = batch_mask;
    static constexpr std::size_t width = batch::size;
};

template <class T>
using mask_t = typename value_traits<T>::mask;

template <class T>
inline constexpr std::size_t width_v = value_traits<T>::width;

// --- scalar overloads -------------------------------------------------------------------
inline double select(bool m, double a, double b) {
    return m ? a : b;
}
inline bool select_mask(bool m, bool a, bool b) {
    return m ? a : b;
}
inline bool any(bool m) {
    return m;
}
inline bool all(bool m) {
    return m;
}
inline bool none(bool m) {
    return !m;
}
inline double sqrt(double x) {
    return std::sqrt(x);
}
inline double exp(double x) {
    return std::exp(x);
}
inline double log(double x) {
    return std::log(x);
}
inline double pow(double x, double y) {
    return std::pow(x, y);
}
inline double abs(double x) {
    return std::fabs(x);
}
inline double min(double a, double b) {
    return a < b ? a : b;
}
inline double max(double a, double b) {
    return a > b ? a : b;
}
inline double sin(double x) {
    return std::sin(x);
}
inline double cos(double x) {
    return std::cos(x);
}
inline double atan(double x) {
    return std::atan(x);
}
inline double ceil(double x) {
    return std::ceil(x);
}
inline double cbrt(double x) {
    return std::cbrt(x);
}
inline bool isfinite(double x) {
    return std::isfinite(x);
}
inline double lane(double x, std::size_t) {
    return x;
}

// --- batch overloads --------------------------------------------------------------------
inline batch select(const batch_mask& m, const batch& a, const batch& b) {
    return xsimd::select(m, a, b);
}
inline batch_mask select_mask(const batch_mask& m, const batch_mask& a, const batch_mask& b) {
    return (m && a) || (!m && b);
}
inline bool any(const batch_mask& m) {
    return xsimd::any(m);
}
inline bool all(const batch_mask& m) {
    return xsimd::all(m);
}
inline bool none(const batch_mask& m) {
    return !xsimd::any(m);
}
inline batch sqrt(const batch& x) {
    return xsimd::sqrt(x);
}
// xsimd's exp turns its argument's exponent into an integer, and its generic code does that by
// a scalar cast, undefined for -inf: the exp(log 0) of a lane that a select then discards. Below
// -746 the result is 0 and above 710 inf anyway, so the argument is held there; NaN passes.
inline batch exp(const batch& x) {
    const batch low(-746.0), high(710.0);
    return xsimd::exp(xsimd::select(x < low, low, xsimd::select(x > high, high, x)));
}
inline batch log(const batch& x) {
    return xsimd::log(x);
}
inline batch pow(const batch& x, const batch& y) {
    return xsimd::pow(x, y);
}
inline batch pow(const batch& x, double y) {
    return xsimd::pow(x, batch(y));
}
inline batch abs(const batch& x) {
    return xsimd::abs(x);
}
inline batch min(const batch& a, const batch& b) {
    return xsimd::min(a, b);
}
inline batch max(const batch& a, const batch& b) {
    return xsimd::max(a, b);
}
inline batch sin(const batch& x) {
    return xsimd::sin(x);
}
inline batch cos(const batch& x) {
    return xsimd::cos(x);
}
inline batch atan(const batch& x) {
    return xsimd::atan(x);
}
inline batch ceil(const batch& x) {
    return xsimd::ceil(x);
}
inline batch cbrt(const batch& x) {
    return xsimd::cbrt(x);
}
inline batch_mask isfinite(const batch& x) {
    return xsimd::isfinite(x);
}
inline double lane(const batch& x, std::size_t i) {
    alignas(64) double buf[batch::size];
    x.store_aligned(buf);
    return buf[i];
}

// Mask helpers that read the same for both value types.
template <class T>
inline T select(const mask_t<T>& m, const T& a, double b) {
    return select(m, a, T(b));
}
// Reduction: largest value over the lanes (the scalar value itself for double).
inline double hmax(double x) {
    return x;
}
inline double hmax(const batch& x) {
    alignas(64) double buf[batch::size];
    x.store_aligned(buf);
    double m = buf[0];
    for (std::size_t i = 1; i < batch::size; ++i) {
        m = buf[i] > m ? buf[i] : m;
    }
    return m;
}
inline double hsum(double x) {
    return x;
}
inline double hsum(const batch& x) {
    return xsimd::hadd(x);
}

} // namespace ifsim::simd
