#pragma once
// Backward-Euler (fully implicit) step of Sanisand 2004 over a strain increment, per lane.
// Design and literature: docs/sanisand-implicit-integration-notes.md.
//
// Why: the explicit scheme must resolve the narrow cone and the stiff kinematic hardening, so
// its substeps grow with the strain increment times G/p (136 per update at 1e-2); backward
// Euler is L-stable and lands on the slow manifold in one step.
//
// Unknowns x (19): sigma_c / p_ref (6, compression positive), alpha (6), z (6),
// dGamma / |deps| (1). All moduli and model functions are taken at the end state; the void
// ratio at the end follows from the strain exactly, e1 = (1 + e_n) exp(-deps_v) - 1.
// Residuals (dimensionless):
//   R_sigma = [sigma - sigma_n - E(end) : (deps - dGamma R)] / p_ref
//   R_alpha = [d (alpha - alpha_n) - k b] / (|d| + k) + tr(alpha)/3 I,  k = (2/3) dGamma b0,
//             d = (alpha - alpha_n):n + <(alpha_n - alpha_in):n>: h = b0/d multiplied out, so
//             the pole of h right after a reversal (d = 0) is not in the residual; the Macaulay
//             bracket is the end-normal form of the alpha_in reset (C0 in deps)
//   R_z     = z - z_n + c_z <-dGamma D> (z_max n + z) + tr(z)/3 I
//   R_f     = ||r - alpha|| - sqrt(2/3) m
// The elastic trial is closed-form: with G, K proportional to sqrt(p) the end-state
// volumetric law is a quadratic in sqrt(p). The Jacobian is a forward difference of the
// residual (only the converged residual sets the result, so its accuracy sets the speed only).

#include <array>
#include <cmath>

#include "kernels/dense_solve.hpp"
#include "kernels/model_api.hpp"
#include "kernels/sanisand_rates.hpp"

namespace ifsim::sanisand {

inline constexpr int be_unknowns = 19;
// Scaled residual (max norm) at which a step has converged; one more Newton correction follows,
// so the result sits at round-off and does not jump with the iteration count.
inline constexpr double be_tolerance = 1.0e-11;
inline constexpr int be_max_iterations = 40;
inline constexpr int be_line_search_halvings = 8;
// Relative forward-difference step of the Jacobian columns (floored at be_fd_floor).
inline constexpr double be_fd_step = 1.0e-7;
inline constexpr double be_fd_floor = 1.0e-2;

// f/p above which the elastic trial is outside the cone (as the explicit scheme's test).
inline constexpr double be_yield_tolerance = 1.0e-9;

template <class T>
using BeVector = DenseVector<T, be_unknowns>;

template <class T>
BeVector<T> select_vector(const simd::mask_t<T>& m, const BeVector<T>& a, const BeVector<T>& b) {
    BeVector<T> r;
    for (int i = 0; i < be_unknowns; ++i) {
        r[i] = simd::select(m, a[i], b[i]);
    }
    return r;
}

// What one backward-Euler step starts from (compression positive).
template <class T>
struct BeStart {
    Sym<T> sigma_n, alpha_n, z_n, alpha_in;
    T e1;          // void ratio at the end of the step
    Sym<T> deps_c; // strain increment
    T p_ref;       // scale of the stress unknowns
    T gamma_ref;   // scale of the multiplier unknown
};

// End state of the unknowns x, with alpha_in the effective one of the residual.
template <class T>
State<T> be_state(const BeStart<T>& b, const BeVector<T>& x) {
    State<T> y{};
    for (int i = 0; i < 6; ++i) {
        y[i] = -x[i] * b.p_ref;
        y[alpha_index + i] = x[6 + i];
        y[z_index + i] = x[12 + i];
        y[alpha_in_index + i] = b.alpha_in[i];
    }
    y[state_index::void_ratio] = b.e1;
    return y;
}

// Residual at x. In lanes outside `plastic` the multiplier is held at 0 and alpha, z at their
// start values (an elastic step), so the system stays regular there.
template <class T>
BeVector<T> be_residual(const SanisandParams& P, const IntegrationSettings& s, const BeStart<T>& b,
                        const BeVector<T>& x, const simd::mask_t<T>& plastic_lanes) {
    State<T> y = be_state(b, x);
    const Point<T> q = point(P, s, y);
    const T c = simd::max(voigt::ddot(voigt::sub(b.alpha_n, b.alpha_in), q.n), T(0.0));
    set_sym_at(y, alpha_in_index, voigt::axpy(b.alpha_n, -c, q.n));
    const Plastic<T> k = plastic(P, q, y);
    const T dG = simd::select(plastic_lanes, x[18] * b.gamma_ref, T(0.0));

    BeVector<T> r;
    const T dv = voigt::trace(b.deps_c);
    const Sym<T> ddev = voigt::deviator(b.deps_c);
    const T inv_p = 1.0 / b.p_ref;
    for (int i = 0; i < 6; ++i) {
        const T dsig =
            2.0 * q.G * (ddev[i] - dG * k.Rdev[i]) + (i < 3 ? q.K * (dv - dG * k.D) : T(0.0));
        r[i] = (x[i] * b.p_ref - b.sigma_n[i] - dsig) * inv_p;
    }
    const T kk = (2.0 / 3.0) * dG * k.b0;
    const T d = k.h_denom;
    // |kk|: an iterate with dGamma < 0 must not put a pole into the weight (roots unchanged)
    const T inv_w = 1.0 / simd::max(simd::abs(d) + simd::abs(kk), T(1.0e-300));
    const T tr_a = (x[6] + x[7] + x[8]) * (1.0 / 3.0);
    const Sym<T> zdev = voigt::deviator(sym_at(y, z_index));
    const T tr_z = (x[12] + x[13] + x[14]) * (1.0 / 3.0);
    const T C = P.c_z * simd::max(-dG * k.D, T(0.0));
    for (int i = 0; i < 6; ++i) {
        const T iso_a = i < 3 ? tr_a : T(0.0);
        const T iso_z = i < 3 ? tr_z : T(0.0);
        const T ra = (d * (q.alpha[i] - b.alpha_n[i]) - kk * k.b[i]) * inv_w + iso_a;
        r[6 + i] = simd::select(plastic_lanes, ra, x[6 + i] - b.alpha_n[i]);
        const T rz = zdev[i] - b.z_n[i] + C * (zdev[i] + P.z_max * q.n[i]) + iso_z;
        r[12 + i] = simd::select(plastic_lanes, rz, x[12 + i] - b.z_n[i]);
    }
    r[18] = simd::select(plastic_lanes, q.f, x[18]);
    return r;
}

template <class T>
T be_max_norm(const BeVector<T>& r) {
    T m(0.0);
    for (const T& v : r) {
        m = simd::max(m, simd::abs(v));
    }
    // a non-finite residual never counts as small
    return simd::select(simd::isfinite(m), m, T(1.0e300));
}

template <class T>
T be_two_norm(const BeVector<T>& r) {
    T m(0.0);
    for (const T& v : r) {
        m += v * v;
    }
    return simd::select(simd::isfinite(m), m, T(1.0e300));
}

// Elastic end state by the closed form: p = p_n + K_hat sqrt(p) deps_v, s = s_n + 2 G(p) de.
template <class T>
Sym<T> be_elastic_trial(const SanisandParams& P, const IntegrationSettings& s,
                        const BeStart<T>& b) {
    const T ee = 2.97 - b.e1;
    const T G_hat = P.G0 * P.p_a * ee * ee / (1.0 + b.e1) / std::sqrt(P.p_a);
    const T K_hat = P.K_over_G * G_hat;
    const T p_n = simd::max(voigt::trace(b.sigma_n) * (1.0 / 3.0), T(s.min_pressure));
    const T a = K_hat * voigt::trace(b.deps_c);
    const T u = 0.5 * (a + simd::sqrt(a * a + 4.0 * p_n));
    const T G = G_hat * u;
    const Sym<T> de = voigt::deviator(b.deps_c);
    const T dp = K_hat * u * voigt::trace(b.deps_c);
    Sym<T> sig;
    for (int i = 0; i < 6; ++i) {
        sig[i] = b.sigma_n[i] + 2.0 * G * de[i] + (i < 3 ? dp : T(0.0));
    }
    return sig;
}

// Start of the plastic Newton: on the cone with the trial's normal n, dGamma from a radial
// return with alpha held, alpha from the closed-form implicit hardening along n with that
// dGamma (the quadratic for d = (alpha - alpha_n):n + c), the trial's mean pressure.
template <class T>
BeVector<T> be_plastic_start(const SanisandParams& P, const IntegrationSettings& s,
                             const BeStart<T>& b, const BeVector<T>& trial) {
    State<T> y = be_state(b, trial);
    const Point<T> q = point(P, s, y);
    const T c = simd::max(voigt::ddot(voigt::sub(b.alpha_n, b.alpha_in), q.n), T(0.0));
    set_sym_at(y, alpha_in_index, voigt::axpy(b.alpha_n, -c, q.n));
    const Plastic<T> k = plastic(P, q, y);
    const T dG = simd::max(q.f, T(0.0)) * q.p / (2.0 * q.G);
    const T kk = (2.0 / 3.0) * dG * k.b0;
    const T A = voigt::ddot(k.b, q.n);
    const T disc = (kk - c) * (kk - c) + 4.0 * kk * simd::max(A + c, T(0.0));
    const T d = simd::max(0.5 * (c - kk + simd::sqrt(disc)), T(1.0e-8));
    const T beta = kk / d;
    const Sym<T> alpha = voigt::axpy(q.alpha, beta / (1.0 + beta), k.b);
    const Sym<T> r = voigt::axpy(alpha, T(sqrt_2_3 * P.m), q.n);
    BeVector<T> x = trial;
    for (int i = 0; i < 6; ++i) {
        x[i] = (q.p * r[i] + (i < 3 ? q.p : T(0.0))) / b.p_ref;
        x[6 + i] = alpha[i];
    }
    x[18] = dG / b.gamma_ref;
    return x;
}

template <class T>
struct BeResult {
    State<T> y;             // end state (alpha_in committed), valid where ok
    simd::mask_t<T> ok;     // converged to an admissible state
    T residual_evaluations; // per lane
};

// One backward-Euler step over deps (mechanical sign) from y in the lanes `lanes`.
template <class T>
BeResult<T> be_step(const SanisandParams& P, const IntegrationSettings& s, const State<T>& y,
                    const Sym<T>& deps, const simd::mask_t<T>& lanes) {
    using Mask = simd::mask_t<T>;
    BeStart<T> b;
    b.sigma_n = voigt::scale(stress_of(y), T(-1.0));
    b.alpha_n = voigt::deviator(sym_at(y, alpha_index));
    b.z_n = voigt::deviator(sym_at(y, z_index));
    b.alpha_in = voigt::deviator(sym_at(y, alpha_in_index));
    b.deps_c = voigt::scale(deps, T(-1.0));
    const T e_n = y[state_index::void_ratio];
    b.e1 = (1.0 + e_n) * simd::exp(-voigt::trace(b.deps_c)) - 1.0;
    b.p_ref = simd::max(voigt::trace(b.sigma_n) * (1.0 / 3.0), T(s.min_pressure));
    b.gamma_ref = simd::max(voigt::norm(deps), T(1.0e-12));

    BeResult<T> out;
    out.residual_evaluations = T(0.0);
    BeVector<T> x;
    const Sym<T> sig_tr = be_elastic_trial(P, s, b);
    for (int i = 0; i < 6; ++i) {
        x[i] = sig_tr[i] / b.p_ref;
        x[6 + i] = b.alpha_n[i];
        x[12 + i] = b.z_n[i];
    }
    x[18] = T(0.0);
    const Point<T> qt = point(P, s, be_state(b, x));
    const Mask plastic_lanes =
        lanes && (qt.f > be_yield_tolerance) && (qt.distance > axis_tolerance);

    if (simd::any(plastic_lanes)) {
        x = select_vector(plastic_lanes, be_plastic_start(P, s, b, x), x);
        BeVector<T> r = be_residual(P, s, b, x, plastic_lanes);
        out.residual_evaluations += simd::select(plastic_lanes, T(1.0), T(0.0));
        Mask working = plastic_lanes;
        Mask met(false);
        Mask done(false);
        for (int it = 0; it < be_max_iterations && simd::any(working); ++it) {
            met = met || (working && (be_max_norm(r) <= be_tolerance));
            // forward-difference Jacobian
            DenseMatrix<T, be_unknowns> J;
            for (int j = 0; j < be_unknowns; ++j) {
                BeVector<T> xp = x;
                const T h = be_fd_step * simd::max(simd::abs(x[j]), T(be_fd_floor));
                xp[j] += h;
                const BeVector<T> rp = be_residual(P, s, b, xp, plastic_lanes);
                for (int i = 0; i < be_unknowns; ++i) {
                    J[i][j] = (rp[i] - r[i]) / h;
                }
            }
            out.residual_evaluations += simd::select(working, T(be_unknowns), T(0.0));
            BeVector<T> dx = r;
            const Mask solved = dense_solve<T, be_unknowns>(J, dx);
            // a singular Jacobian at a met tolerance (kinks after a reversal) keeps the iterate
            done = done || (working && met && !solved);
            Mask failed = working && !solved && !met;
            // A lane that met the tolerance takes one full correction more and stops.
            const Mask polish = working && solved && met;
            Mask pending = working && solved && !met;
            BeVector<T> xp;
            for (int i = 0; i < be_unknowns; ++i) {
                xp[i] = simd::select(polish, x[i] - dx[i], x[i]);
            }
            x = xp;
            // backtracking line search on ||R||^2 for the others
            const T r0 = be_two_norm(r);
            T lambda(1.0);
            for (int ls = 0; ls <= be_line_search_halvings && simd::any(pending); ++ls) {
                BeVector<T> xt;
                for (int i = 0; i < be_unknowns; ++i) {
                    xt[i] = x[i] - lambda * dx[i];
                }
                const BeVector<T> rt = be_residual(P, s, b, xt, plastic_lanes);
                out.residual_evaluations += simd::select(pending, T(1.0), T(0.0));
                // the last halving is taken when finite: a kink can block the decrease test
                const Mask last =
                    Mask(ls == be_line_search_halvings) && (be_two_norm(rt) < 1.0e299);
                const Mask accept =
                    pending && ((be_two_norm(rt) <= (1.0 - 1.0e-4 * lambda) * r0) || last);
                x = select_vector(accept, xt, x);
                r = select_vector(accept, rt, r);
                pending = pending && !accept;
                lambda = simd::select(pending, 0.5 * lambda, lambda);
            }
            failed = failed || pending;
            done = done || polish;
            working = working && !polish && !failed;
        }
        // a lane that met the tolerance in the last line search
        done = done || (working && (be_max_norm(r) <= be_tolerance));
        const Mask converged = plastic_lanes && done;
        // the end state must be one the model admits: a hardening denominator d > 0 (h > 0),
        // a non-negative multiplier, the pressure above the floor
        State<T> ye = be_state(b, x);
        const Point<T> qe = point(P, s, ye);
        const T c = simd::max(voigt::ddot(voigt::sub(b.alpha_n, b.alpha_in), qe.n), T(0.0));
        const T d = voigt::ddot(voigt::sub(qe.alpha, b.alpha_n), qe.n) + c;
        const Mask sane =
            (d > 0.0) && (x[18] >= -1.0e-12) &&
            (voigt::trace(voigt::scale(stress_of(ye), T(-1.0))) >= 3.0 * s.min_pressure);
        // alpha_in: kept, or alpha_n where the end normal reverses the loading (c term inactive)
        const Mask reversal = voigt::ddot(voigt::sub(b.alpha_n, b.alpha_in), qe.n) <= 0.0;
        set_sym_at(ye, alpha_in_index, voigt::select(reversal, b.alpha_n, b.alpha_in));
        remove_traces(ye);
        out.y = select_state<T, n_state>(plastic_lanes, ye, y);
        out.ok = !plastic_lanes || (converged && sane && state_finite<T, n_state>(ye));
    } else {
        out.y = y;
        out.ok = Mask(true);
    }
    // elastic lanes: the trial, alpha, z and alpha_in unchanged
    const Mask elastic = lanes && !plastic_lanes;
    State<T> yel = y;
    set_stress(yel, voigt::scale(sig_tr, T(-1.0)));
    yel[state_index::void_ratio] = b.e1;
    out.y = select_state<T, n_state>(elastic, yel, out.y);
    out.ok = out.ok && (!elastic || (voigt::trace(sig_tr) >= 3.0 * s.min_pressure));
    out.ok = out.ok && lanes;
    return out;
}

} // namespace ifsim::sanisand
