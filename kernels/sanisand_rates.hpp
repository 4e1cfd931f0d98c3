#pragma once
// The rate equations of Sanisand 2004 (Dafalias & Manzari 2004) at one state, for one strain
// increment, written once over the value type T. Equations and choices: docs/models.md (Sanisand).
//
// Internally compression is positive (sigma_c = -sigma, deps_c = -deps), as in the paper; the
// ratio tensors r, alpha, z, n are the same in both conventions. The flat state stores the
// mechanical-sign stress.

#include <cmath>

#include "kernels/model_api.hpp"
#include "kernels/sanisand_params.hpp"

namespace ifsim::sanisand {

inline constexpr int alpha_index = 7;
inline constexpr int z_index = 13;
inline constexpr int alpha_in_index = 19;
inline constexpr int n_state = 25;

inline constexpr double sqrt_2_3 = 0.81649658092772603273; // sqrt(2/3)

// Smallest (alpha - alpha_in):n used in h = b0 / ((alpha - alpha_in):n): right after a load
// reversal the denominator is zero and h is capped instead of infinite.
inline constexpr double h_denominator_min = 1.0e-10;
// ||r - alpha|| below this has no defined normal n (the stress ratio sits on the cone axis).
inline constexpr double axis_tolerance = 1.0e-14;

template <class T>
using State = StateVec<T, n_state>;

// Quantities at a state that both elastic and plastic rates need.
template <class T>
struct Point {
    T p;          // mean pressure, floored at p_min (compression positive)
    T e;          // void ratio
    Sym<T> r;     // stress ratio dev(sigma)/p
    Sym<T> alpha; // back-stress ratio
    T G, K;       // hypoelastic moduli
    Sym<T> n;     // unit normal of the cone (zero on the axis)
    T distance;   // ||r - alpha||
    T f;          // yield function divided by p: ||r - alpha|| - sqrt(2/3) m
};

template <class T>
Point<T> point(const SanisandParams& P, const IntegrationSettings& s, const State<T>& y) {
    Point<T> q;
    const Sym<T> sigma = voigt::scale(stress_of(y), T(-1.0));
    q.p = simd::max(voigt::trace(sigma) * (1.0 / 3.0), T(s.min_pressure));
    q.e = y[state_index::void_ratio];
    q.r = voigt::scale(voigt::deviator(sigma), 1.0 / q.p);
    // alpha is deviatoric by definition; its trace is a spurious, stiff mode of the explicit
    // update (decay rate ~ (2/3) L h sqrt(3/2)/m) seeded by round-off, so it is never used
    q.alpha = voigt::deviator(sym_at(y, alpha_index));
    // G = G0 p_a (2.97 - e)^2 / (1 + e) (p/p_a)^(1/2), K from nu
    const T ee = 2.97 - q.e;
    q.G = P.G0 * P.p_a * ee * ee / (1.0 + q.e) * simd::sqrt(q.p / P.p_a);
    q.K = P.K_over_G * q.G;
    const Sym<T> ra = voigt::sub(q.r, q.alpha);
    q.distance = voigt::norm(ra);
    const T inv = simd::select(q.distance > axis_tolerance,
                               1.0 / simd::max(q.distance, T(axis_tolerance)), T(0.0));
    q.n = voigt::scale(ra, inv);
    q.f = q.distance - sqrt_2_3 * P.m;
    return q;
}

// Yield function f/p of a flat state (dimensionless).
template <class T>
T yield_ratio(const SanisandParams& P, const IntegrationSettings& s, const State<T>& y) {
    return point(P, s, y).f;
}

// Plastic quantities at a state for the loading direction n.
template <class T>
struct Plastic {
    T N;         // n:alpha + sqrt(2/3) m, so that df/dsigma = n - (N/3) I
    Sym<T> Rdev; // deviatoric flow direction B n - C (n^2 - I/3)
    T D;         // dilatancy (positive = contraction)
    T Kp;        // plastic modulus (2/3) p h (b:n)
    T h;         // hardening coefficient
    T b0;        // h times its denominator (alpha - alpha_in):n
    T h_denom;   // (alpha - alpha_in):n, not floored
    Sym<T> b;    // alpha^b - alpha
    T n_Rdev;    // n : Rdev (= 1 for unclipped Lode angles)
};

template <class T>
Plastic<T> plastic(const SanisandParams& P, const Point<T>& q, const State<T>& y) {
    Plastic<T> k;
    const Sym<T>& n = q.n;
    const Sym<T> n2 = voigt::square(n);
    const T tr_n3 = voigt::ddot(n2, n);
    // Lode angle of n: cos 3 theta = sqrt(6) tr n^3 (+1 in triaxial compression)
    const T cos3t = simd::max(T(-1.0), simd::min(T(1.0), std::sqrt(6.0) * tr_n3));
    // g(theta, c) = 2c / ((1 + c) - (1 - c) cos 3 theta)
    const T g = 2.0 * P.c_eff / ((1.0 + P.c_eff) - (1.0 - P.c_eff) * cos3t);
    // critical state line and state parameter psi = e - e_c (p floored)
    const T e_c = P.e0 - P.lambda_c * simd::pow(q.p / P.p_a, T(P.xi));
    const T psi = q.e - e_c;
    const T gM = g * P.M_c_eff;
    // bounding (Eq. 34 with kappa n_b) and dilatancy image ratios, as multiples of n
    const T ab = sqrt_2_3 * (gM * simd::exp(-P.n_b_eff * psi) - P.m);
    const T ad = sqrt_2_3 * (gM * simd::exp(P.n_d * psi) - P.m);
    const T alpha_n = voigt::ddot(q.alpha, n);
    k.b = voigt::axpy(voigt::scale(q.alpha, T(-1.0)), ab, n);
    const T b_n = ab - alpha_n;
    const T d_n = ad - alpha_n;
    // kinematic hardening: h = b0 / ((alpha - alpha_in):n), b0 = G0 h0 (1 - c_h e) (p/p_a)^-1/2;
    // 1 - c_h e is kept positive so h keeps its sign beyond the calibrated range of e
    const T b0 = P.G0 * P.h0 * simd::max(1.0 - P.c_h * q.e, T(1.0e-3)) / simd::sqrt(q.p / P.p_a);
    const Sym<T> alpha_in = sym_at(y, alpha_in_index);
    const T denom = voigt::ddot(voigt::sub(q.alpha, alpha_in), n);
    k.b0 = b0;
    k.h_denom = denom;
    k.h = b0 / simd::max(denom, T(h_denominator_min));
    k.Kp = (2.0 / 3.0) * q.p * k.h * b_n;
    // dilatancy with fabric, Eq. 35: A_d = kappa A0 (1 + <z:n>)
    const T zn = voigt::ddot(sym_at(y, z_index), n);
    k.D = P.A0_eff * (1.0 + simd::max(zn, T(0.0))) * d_n;
    // B and C of the Lode-angle dependent flow direction
    const T B = 1.0 + 1.5 * P.lode_k * g * cos3t;
    const T C = 3.0 * std::sqrt(1.5) * P.lode_k * g;
    for (int i = 0; i < 6; ++i) {
        const T iso = i < 3 ? T(1.0 / 3.0) : T(0.0);
        k.Rdev[i] = B * n[i] - C * (n2[i] - iso);
    }
    k.n_Rdev = B - C * tr_n3;
    k.N = alpha_n + sqrt_2_3 * P.m;
    return k;
}

// Loading numerator 2G n:de - K deps_v N = (df/dsigma):E:deps (compression-positive strain).
template <class T>
T loading_numerator(const Point<T>& q, const Plastic<T>& k, const Sym<T>& deps_c) {
    return 2.0 * q.G * voigt::ddot(q.n, deps_c) - q.K * voigt::trace(deps_c) * k.N;
}

// Denominator Kp + (df/dsigma):E:R of the loading index, floored at a tenth of its elastic part
// 2G n:R'. Softening (Kp < 0) beyond that occurs only when h is huge while alpha lies beyond
// the bounding surface (b:n < 0), e.g. right after a reversal there or when a start state lies
// outside the bounding surface: the strain-driven problem then has no solution with L > 0
// (den <= 0, a snap-back), and L = num/den would pass through a pole as h decays. The floor
// makes it strong but bounded softening back towards the bounding surface instead. Calibrated
// softening (post-peak dense sand: |Kp| ~ 0.2 G) is far from the floor.
template <class T>
T loading_denominator(const Point<T>& q, const Plastic<T>& k) {
    const T den = k.Kp + 2.0 * q.G * k.n_Rdev - q.K * k.D * k.N;
    return simd::max(den, 0.1 * 2.0 * q.G * k.n_Rdev);
}

// The hardening coefficient that belongs to the floored denominator den. The floor raises Kp
// to Kp + (den - den_raw); with Kp = (2/3) p h b:n that is h scaled by the ratio of the two,
// a factor in [0, 1] in softening (Kp < 0). Why: right after a reversal beyond the bounding
// surface h sits at its cap (b0 / 1e-10); the floored L times that h moved alpha by O(1) in a
// substep of 1e-15 strain, the drift correction put it back, the next substep saw a reversal
// again, and the integration stalled at its smallest substep for its whole attempt budget
// (docs/models.md). With this h, alpha moves as the consistency condition demands.
template <class T>
T consistent_h(const Point<T>& q, const Plastic<T>& k, const T& den) {
    const T den_raw = k.Kp + 2.0 * q.G * k.n_Rdev - q.K * k.D * k.N;
    const T Kp_floored = k.Kp + (den - den_raw);
    const T ratio = Kp_floored / simd::min(k.Kp, T(-1.0e-300));
    return simd::select(k.Kp < 0.0, k.h * simd::max(T(0.0), simd::min(T(1.0), ratio)), k.h);
}

// Increment of the flat state for the mechanical strain increment de (explicit Euler rate).
// Plasticity acts in lanes of plastic_allowed whose loading numerator is positive.
template <class T>
State<T> increment(const SanisandParams& P, const IntegrationSettings& s, const State<T>& y,
                   const Sym<T>& de, const simd::mask_t<T>& plastic_allowed) {
    const Point<T> q = point(P, s, y);
    const Sym<T> dc = voigt::scale(de, T(-1.0));
    const T dv = voigt::trace(dc);
    const Sym<T> ddev = voigt::deviator(dc);
    Sym<T> dsig; // compression positive
    for (int i = 0; i < 6; ++i) {
        dsig[i] = 2.0 * q.G * ddev[i] + (i < 3 ? q.K * dv : T(0.0));
    }
    State<T> dy;
    for (auto& v : dy) {
        v = T(0.0);
    }
    // de_void = -(1 + e) deps_v (compression positive)
    dy[state_index::void_ratio] = -(1.0 + q.e) * dv;

    const simd::mask_t<T> allowed = plastic_allowed && (q.distance > axis_tolerance);
    if (simd::any(allowed)) {
        const Plastic<T> k = plastic(P, q, y);
        const T num = loading_numerator(q, k, dc);
        const T den = loading_denominator(q, k);
        const simd::mask_t<T> loading = allowed && (num > 0.0);
        const T L = simd::select(loading, num / den, T(0.0));
        // dsigma = E:deps - L (2G R' + K D I)
        for (int i = 0; i < 6; ++i) {
            dsig[i] -= L * (2.0 * q.G * k.Rdev[i] + (i < 3 ? q.K * k.D : T(0.0)));
        }
        // dalpha = L (2/3) h b, with h consistent with the floored denominator
        set_sym_at(dy, alpha_index, voigt::scale(k.b, L * (2.0 / 3.0) * consistent_h(q, k, den)));
        // dz = -c_z <-deps_v^p> (z_max n + z), deps_v^p = L D
        const T dil = simd::max(-L * k.D, T(0.0));
        const Sym<T> target = voigt::axpy(voigt::deviator(sym_at(y, z_index)), T(P.z_max), q.n);
        set_sym_at(dy, z_index, voigt::scale(target, -P.c_z * dil));
    }
    set_stress(dy, voigt::scale(dsig, T(-1.0)));
    return dy;
}

// Moves alpha along n so the state lies exactly on f = 0: alpha = r - sqrt(2/3) m n.
template <class T>
void project_onto_cone(const SanisandParams& P, const IntegrationSettings& s, State<T>& y,
                       const simd::mask_t<T>& lanes) {
    const Point<T> q = point(P, s, y);
    const simd::mask_t<T> ok = lanes && (q.distance > axis_tolerance);
    const Sym<T> alpha = voigt::axpy(q.r, T(-sqrt_2_3 * P.m), q.n);
    set_sym_at(y, alpha_index, voigt::select(ok, alpha, q.alpha));
}

// Removes the (spurious) traces of alpha, z and alpha_in, which are deviatoric by definition.
template <class T>
void remove_traces(State<T>& y) {
    for (int offset : {alpha_index, z_index, alpha_in_index}) {
        set_sym_at(y, offset, voigt::deviator(sym_at(y, offset)));
    }
}

} // namespace ifsim::sanisand
