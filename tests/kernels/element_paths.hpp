#pragma once
// Single-point element paths for the kernel tests: strain-controlled steps and mixed
// strain/stress-controlled steps (drained triaxial compression at constant lateral stress),
// driven through the guarded entry point material_update<Hypoplasticity, double>. The mixed
// steps solve for the strain of the stress-controlled components by a Newton iteration with a
// finite-difference tangent of the integrated update (see mixed_step). Also small helpers: limit
// void ratios, invariants, rotations, SIMD lanes <-> scalar points.

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

#include "kernels/hypoplasticity.hpp"
#include "kernels/material_update.hpp"

namespace ifsim::test {

using HypoState = Hypoplasticity::State<double>;

inline HypoState hypo_state(const Sym<double>& stress, double e,
                            const Sym<double>& h = voigt::zero<double>()) {
    HypoState y{};
    set_stress(y, stress);
    y[state_index::void_ratio] = e;
    set_sym_at(y, Hypoplasticity::h_index, h);
    return y;
}

inline Sym<double> isotropic(double value) {
    return voigt::scale(voigt::identity<double>(), value);
}

// Limit void ratio e_x0 exp(-(3p/h_s)^n) of the Bauer law at mean pressure p.
inline double bauer(const HypoplasticityParams& p, double e_x0, double pressure) {
    return e_x0 * std::exp(-std::pow(3.0 * pressure / p.h_s, p.n));
}

// Critical stress ratio q/p in triaxial compression for friction angle phi.
inline double critical_ratio_compression(double phi) {
    return 6.0 * std::sin(phi) / (3.0 - std::sin(phi));
}

// Principal invariants of a symmetric tensor in Voigt (tensor shear) storage.
struct Invariants {
    double I1, I2, I3;
};
inline Invariants invariants(const Sym<double>& s) {
    const double I1 = s[0] + s[1] + s[2];
    const double I2 =
        s[0] * s[1] + s[1] * s[2] + s[2] * s[0] - s[3] * s[3] - s[4] * s[4] - s[5] * s[5];
    const double I3 = s[0] * (s[1] * s[2] - s[5] * s[5]) - s[3] * (s[3] * s[2] - s[5] * s[4]) +
                      s[4] * (s[3] * s[5] - s[1] * s[4]);
    return {I1, I2, I3};
}

// Mobilised Matsuoka-Nakai friction angle of a compressive stress state (any Lode angle).
inline double matsuoka_nakai_angle(const Sym<double>& s) {
    const Invariants v = invariants(s);
    const double k = v.I1 * v.I2 / v.I3;
    return std::asin(std::sqrt((k - 9.0) / (k - 1.0)));
}

// Deviatoric stress q = sqrt(3/2 |dev s|^2), mean pressure p > 0 in compression.
inline double deviatoric_q(const Sym<double>& s) {
    return std::sqrt(1.5) * voigt::norm(voigt::deviator(s));
}

inline UpdateStats<double> strain_step(const HypoplasticityParams& p, const IntegrationSettings& s,
                                       HypoState& y, const Sym<double>& deps,
                                       double fixed_substeps = 0.0) {
    SubstepControl<double> control;
    control.fixed_substeps = fixed_substeps;
    UpdateStats<double> stats;
    material_update<Hypoplasticity, double>(p, s, control, y, deps, stats);
    return stats;
}

// Solves A x = b for n <= 6 unknowns by Gaussian elimination with partial pivoting.
template <int Max>
inline bool solve_small(std::array<std::array<double, Max>, Max> A, std::array<double, Max>& b,
                        int n) {
    for (int c = 0; c < n; ++c) {
        int piv = c;
        for (int r = c + 1; r < n; ++r) {
            if (std::fabs(A[r][c]) > std::fabs(A[piv][c])) {
                piv = r;
            }
        }
        if (A[piv][c] == 0.0) {
            return false;
        }
        std::swap(A[piv], A[c]);
        std::swap(b[piv], b[c]);
        for (int r = c + 1; r < n; ++r) {
            const double f = A[r][c] / A[c][c];
            for (int k = c; k < n; ++k) {
                A[r][k] -= f * A[c][k];
            }
            b[r] -= f * b[c];
        }
    }
    for (int c = n - 1; c >= 0; --c) {
        for (int k = c + 1; k < n; ++k) {
            b[c] -= A[c][k] * b[k];
        }
        b[c] /= A[c][c];
    }
    return true;
}

// One mixed-control step. Components with stress_controlled[j] end at stress target[j]; the
// others take the strain increment deps[j]. On return deps holds the full increment used.
//
// Newton on the unknown strains. The Jacobian is a forward difference of the integrated update
// with the substep count frozen (equal substeps: a smooth map of deps). The residual uses the
// adaptive update; its substep choice makes sigma(deps) jump by ~tolerance where an accept
// decision flips, so after a few iterations the residual is frozen to equal substeps as well and
// the iteration can meet a tight tolerance. The frozen count is the largest adaptive count seen,
// so the equal substeps are no longer than the adaptive ones on average (this keeps them below
// the stability limit ~2R of the intergranular strain, see test_integration.cpp).
struct MixedResult {
    bool converged = false;
    int iterations = 0;
    UpdateStats<double> stats;
};

inline MixedResult mixed_step(const HypoplasticityParams& p, const IntegrationSettings& s,
                              HypoState& y, const std::array<bool, 6>& stress_controlled,
                              Sym<double>& deps, const Sym<double>& target,
                              double rel_tolerance = 1.0e-10, int max_iterations = 30) {
    std::array<int, 6> idx{};
    int n = 0;
    for (int j = 0; j < 6; ++j) {
        if (stress_controlled[j]) {
            idx[n++] = j;
        }
    }
    MixedResult res;
    const double scale = std::max(voigt::norm(stress_of(y)), 1.0);
    constexpr int adaptive_iterations = 4;
    double frozen = 0.0;
    for (int it = 0; it < max_iterations; ++it) {
        HypoState trial = y;
        res.stats = strain_step(p, s, trial, deps, it < adaptive_iterations ? 0.0 : frozen);
        res.iterations = it + 1;
        if (res.stats.status < -0.5) {
            return res;
        }
        frozen = std::max(frozen, res.stats.substeps);
        std::array<double, 6> r{};
        double rmax = 0.0;
        for (int k = 0; k < n; ++k) {
            r[k] = target[idx[k]] - trial[idx[k]];
            rmax = std::max(rmax, std::fabs(r[k]));
        }
        if (rmax <= rel_tolerance * scale) {
            y = trial;
            res.converged = true;
            return res;
        }
        HypoState base = y;
        strain_step(p, s, base, deps, frozen);
        const double h = 1.0e-7 * std::max(voigt::norm(deps), 1.0e-8);
        std::array<std::array<double, 6>, 6> A{};
        for (int b = 0; b < n; ++b) {
            Sym<double> d = deps;
            d[idx[b]] += h;
            HypoState pert = y;
            strain_step(p, s, pert, d, frozen);
            for (int a = 0; a < n; ++a) {
                A[a][b] = (pert[idx[a]] - base[idx[a]]) / h;
            }
        }
        if (!solve_small<6>(A, r, n)) {
            return res;
        }
        for (int k = 0; k < n; ++k) {
            deps[idx[k]] += r[k];
        }
    }
    return res;
}

// Drained triaxial compression (axis 1) at constant lateral stress: eps_11 is prescribed,
// sigma_22 = sigma_33 stay at their start values, shear strains stay zero.
struct TriaxialResult {
    bool ok = true;
    int steps = 0;
    int max_newton = 0;
};
inline TriaxialResult drained_triaxial(const HypoplasticityParams& p, const IntegrationSettings& s,
                                       HypoState& y, double axial_strain, int steps) {
    const std::array<bool, 6> sc{false, true, true, false, false, false};
    const Sym<double> target = stress_of(y);
    Sym<double> deps{-axial_strain / steps, 0.0, 0.0, 0.0, 0.0, 0.0};
    TriaxialResult out;
    for (int k = 0; k < steps; ++k) {
        // Start from the lateral strains of the previous step (a good Newton guess).
        const MixedResult r = mixed_step(p, s, y, sc, deps, target);
        out.max_newton = std::max(out.max_newton, r.iterations);
        out.steps = k + 1;
        if (!r.converged) {
            out.ok = false;
            return out;
        }
    }
    return out;
}

// A rotation from axis-angle (the axis is normalised here) as a 3x3 matrix.
using Mat3 = std::array<std::array<double, 3>, 3>;
inline Mat3 rotation(std::array<double, 3> axis, double angle) {
    const double n = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
    for (double& a : axis) {
        a /= n;
    }
    const double c = std::cos(angle), sn = std::sin(angle), t = 1.0 - c;
    const double x = axis[0], yv = axis[1], z = axis[2];
    return {{{t * x * x + c, t * x * yv - sn * z, t * x * z + sn * yv},
             {t * x * yv + sn * z, t * yv * yv + c, t * yv * z - sn * x},
             {t * x * z - sn * yv, t * yv * z + sn * x, t * z * z + c}}};
}
inline Mat3 to_matrix(const Sym<double>& a) {
    return {{{a[0], a[3], a[4]}, {a[3], a[1], a[5]}, {a[4], a[5], a[2]}}};
}
inline Sym<double> to_voigt(const Mat3& m) {
    return {m[0][0],
            m[1][1],
            m[2][2],
            0.5 * (m[0][1] + m[1][0]),
            0.5 * (m[0][2] + m[2][0]),
            0.5 * (m[1][2] + m[2][1])};
}
// Q a Q^T
inline Sym<double> rotate(const Mat3& Q, const Sym<double>& a) {
    const Mat3 A = to_matrix(a);
    Mat3 r{};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            double v = 0.0;
            for (int k = 0; k < 3; ++k) {
                for (int l = 0; l < 3; ++l) {
                    v += Q[i][k] * A[k][l] * Q[j][l];
                }
            }
            r[i][j] = v;
        }
    }
    return to_voigt(r);
}

// --- SIMD lanes <-> scalar points -----------------------------------------------------------

template <std::size_t N>
inline StateVec<simd::batch, N> to_batch(const std::vector<StateVec<double, N>>& ys) {
    StateVec<simd::batch, N> y;
    for (std::size_t k = 0; k < N; ++k) {
        alignas(64) double buf[simd::lanes];
        for (std::size_t l = 0; l < simd::lanes; ++l) {
            buf[l] = ys[l][k];
        }
        y[k] = simd::batch::load_aligned(buf);
    }
    return y;
}
inline Sym<simd::batch> sym_batch(const std::vector<Sym<double>>& ds) {
    Sym<simd::batch> d;
    for (int k = 0; k < 6; ++k) {
        alignas(64) double buf[simd::lanes];
        for (std::size_t l = 0; l < simd::lanes; ++l) {
            buf[l] = ds[l][k];
        }
        d[k] = simd::batch::load_aligned(buf);
    }
    return d;
}
template <std::size_t N>
inline StateVec<double, N> lane_of(const StateVec<simd::batch, N>& y, std::size_t l) {
    StateVec<double, N> r;
    for (std::size_t k = 0; k < N; ++k) {
        r[k] = simd::lane(y[k], l);
    }
    return r;
}
inline UpdateStats<double> stats_lane(const UpdateStats<simd::batch>& s, std::size_t l) {
    UpdateStats<double> r;
    r.status = simd::lane(s.status, l);
    r.substeps = simd::lane(s.substeps, l);
    r.rejected = simd::lane(s.rejected, l);
    r.rate_evaluations = simd::lane(s.rate_evaluations, l);
    return r;
}

} // namespace ifsim::test
