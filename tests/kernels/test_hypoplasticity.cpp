// Tests of the hypoplastic kernel (von Wolffersdorff 1996 + intergranular strain, Niemunis &
// Herle 1997 + roughness, paper Eqs. 30-32) against an independent 3x3-matrix implementation of
// the equations, against the limits the theory demands (critical state, Bauer compression law,
// isotropy, the intergranular strain stiffness multipliers), and scalar path vs SIMD path.

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "kernels/hypoplasticity.hpp"
#include "kernels/parameter_sets.hpp"
#include "tests/kernels/element_paths.hpp"

namespace ifsim {
namespace {

// Measured numbers go into the test report (RecordProperty) in scientific notation.
std::string sci(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3e", x);
    return buf;
}

using test::HypoState;
using test::Mat3;

// --- independent reference of the rate equations (plain 3x3 matrices, written from the papers)

Mat3 mat_scale(const Mat3& a, double s) {
    Mat3 r{};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            r[i][j] = a[i][j] * s;
        }
    }
    return r;
}
Mat3 mat_add(const Mat3& a, const Mat3& b) {
    Mat3 r{};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            r[i][j] = a[i][j] + b[i][j];
        }
    }
    return r;
}
Mat3 mat_mul(const Mat3& a, const Mat3& b) {
    Mat3 r{};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            for (int k = 0; k < 3; ++k) {
                r[i][j] += a[i][k] * b[k][j];
            }
        }
    }
    return r;
}
double contract(const Mat3& a, const Mat3& b) {
    double s = 0.0;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            s += a[i][j] * b[i][j];
        }
    }
    return s;
}
double mat_trace(const Mat3& a) {
    return a[0][0] + a[1][1] + a[2][2];
}
Mat3 eye() {
    return {{{1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}}};
}

struct ReferenceRate {
    Mat3 stress;
    Mat3 h;
    double e;
};

// Rates (T, e, h) for the strain rate D, no safeguards (the state must be admissible).
ReferenceRate reference_rate(const HypoplasticityParams& p, const Mat3& T, double e, const Mat3& h,
                             const Mat3& D) {
    const double phi = p.roughness * p.phi_c;
    const double alpha = p.alpha * p.roughness * p.roughness;
    const double a =
        std::sqrt(3.0) * (3.0 - std::sin(phi)) / (2.0 * std::sqrt(2.0) * std::sin(phi));
    const double trT = mat_trace(T);
    const Mat3 Th = mat_scale(T, 1.0 / trT);
    const Mat3 Ts = mat_add(Th, mat_scale(eye(), -1.0 / 3.0));
    const double tan_psi = std::sqrt(3.0) * std::sqrt(contract(Ts, Ts));
    const double ts2 = contract(Ts, Ts);
    const double cos3t =
        ts2 > 0.0 ? -std::sqrt(6.0) * mat_trace(mat_mul(Ts, mat_mul(Ts, Ts))) / std::pow(ts2, 1.5)
                  : 1.0;
    const double F =
        std::sqrt(tan_psi * tan_psi / 8.0 +
                  (2.0 - tan_psi * tan_psi) / (2.0 + std::sqrt(2.0) * tan_psi * cos3t)) -
        tan_psi / (2.0 * std::sqrt(2.0));
    const double bauer = std::exp(-std::pow(-trT / p.h_s, p.n));
    const double ei = p.e_i0 * bauer, ec = p.e_c0 * bauer, ed = p.e_d0 * bauer;
    const double fd = std::pow((e - ed) / (ec - ed), alpha);
    const double fe = std::pow(ec / e, p.beta);
    const double fb =
        p.h_s / p.n * std::pow(p.e_i0 / p.e_c0, p.beta) * (1.0 + ei) / ei *
        std::pow(-trT / p.h_s, 1.0 - p.n) /
        (3.0 + a * a - a * std::sqrt(3.0) * std::pow((p.e_i0 - p.e_d0) / (p.e_c0 - p.e_d0), alpha));
    const double k = fb * fe / contract(Th, Th);
    auto L = [&](const Mat3& X) {
        return mat_scale(mat_add(mat_scale(X, F * F), mat_scale(Th, a * a * contract(Th, X))), k);
    };
    const Mat3 N = mat_scale(mat_add(Th, Ts), k * fd * a * F);
    const double dnorm = std::sqrt(contract(D, D));

    ReferenceRate r;
    r.e = (1.0 + e) * mat_trace(D);
    if (!p.intergranular_strain) {
        r.stress = mat_add(L(D), mat_scale(N, dnorm));
        r.h = Mat3{};
        return r;
    }
    const double hn = std::sqrt(contract(h, h));
    const double rho = std::min(hn / p.R, 1.0);
    const Mat3 hd = hn > 0.0 ? mat_scale(h, 1.0 / hn) : Mat3{};
    const double hD = contract(hd, D);
    const double rc = std::pow(rho, p.chi);
    const Mat3 base = mat_scale(L(D), rc * p.m_T + (1.0 - rc) * p.m_R);
    if (hD > 0.0) {
        r.stress = mat_add(
            base, mat_add(mat_scale(L(hd), rc * (1.0 - p.m_T) * hD), mat_scale(N, rc * hD)));
        r.h = mat_add(D, mat_scale(hd, -std::pow(rho, p.beta_R) * hD));
    } else {
        r.stress = mat_add(base, mat_scale(L(hd), rc * (p.m_R - p.m_T) * hD));
        r.h = D;
    }
    return r;
}

// --- random admissible states --------------------------------------------------------------

struct Sampler {
    std::mt19937_64 rng{20220517};
    double uniform(double lo, double hi) { return std::uniform_real_distribution<>(lo, hi)(rng); }
    test::Mat3 rotation() {
        return test::rotation({uniform(-1, 1), uniform(-1, 1), uniform(-1, 1) + 1e-3},
                              uniform(0.0, 2.0 * std::numbers::pi));
    }
    // Compressive stress well inside the Matsuoka-Nakai cone, random principal axes.
    Sym<double> stress(double p_lo = 20.0, double p_hi = 400.0) {
        const double pm = uniform(p_lo, p_hi);
        const Sym<double> principal{-pm * uniform(0.6, 1.6),
                                    -pm * uniform(0.6, 1.6),
                                    -pm * uniform(0.6, 1.6),
                                    0.0,
                                    0.0,
                                    0.0};
        return test::rotate(rotation(), principal);
    }
    Sym<double> direction() {
        Sym<double> d{};
        for (double& v : d) {
            v = uniform(-1.0, 1.0);
        }
        return voigt::scale(d, 1.0 / voigt::norm(d));
    }
    // Void ratio between e_d and e_i at the stress.
    double void_ratio(const HypoplasticityParams& p, const Sym<double>& s) {
        const double pm = mean_pressure(s);
        return uniform(1.02 * test::bauer(p, p.e_d0, pm), 0.98 * test::bauer(p, p.e_i0, pm));
    }
    HypoState state(const HypoplasticityParams& p) {
        const Sym<double> s = stress();
        return test::hypo_state(s, void_ratio(p, s),
                                voigt::scale(direction(), p.R * uniform(0.0, 1.0)));
    }
};

double rel_diff(const Sym<double>& a, const Sym<double>& b) {
    return voigt::norm(voigt::sub(a, b)) / std::max(voigt::norm(b), 1e-300);
}

HypoplasticityParams prepared(HypoplasticityParams p, bool igs, double kappa = 1.0) {
    p.intergranular_strain = igs;
    p.roughness = kappa;
    p.prepare();
    return p;
}

using test::lane_of;
using test::sym_batch;
using test::to_batch;

// ------------------------------------------------------------------------------------------
// Rate equations against the independent reference.

TEST(HypoplasticRate, EulerIncrementMatchesIndependentReference) {
    Sampler smp;
    const IntegrationSettings s;
    for (const bool igs : {false, true}) {
        for (const double kappa : {1.0, 0.6}) {
            for (const auto& base : {parameter_sets::hypoplasticity_l4c(),
                                     parameter_sets::hypoplasticity_karlsruhe()}) {
                const HypoplasticityParams p = prepared(base, igs, kappa);
                for (int trial = 0; trial < 200; ++trial) {
                    const HypoState y = smp.state(p);
                    // Half of the directions along +-h to hit both branches and rho = 1.
                    Sym<double> d = smp.direction();
                    if (trial % 4 == 1) {
                        d = sym_at(y, 7);
                    } else if (trial % 4 == 2) {
                        d = voigt::scale(sym_at(y, 7), -1.0);
                    }
                    if (voigt::norm(d) == 0.0) {
                        d = smp.direction();
                    }
                    d = voigt::scale(d, 1.0e-4 / voigt::norm(d));
                    const HypoState dy = Hypoplasticity::euler_increment(p, s, y, d);
                    const ReferenceRate ref =
                        reference_rate(p, test::to_matrix(stress_of(y)), y[6],
                                       test::to_matrix(sym_at(y, 7)), test::to_matrix(d));
                    EXPECT_LT(rel_diff(stress_of(dy), test::to_voigt(ref.stress)), 1e-12)
                        << "igs " << igs << " kappa " << kappa << " trial " << trial;
                    EXPECT_NEAR(dy[6], ref.e, 1e-14 * std::fabs(ref.e) + 1e-300);
                    if (igs) {
                        // Relative to |D|: along h the two terms of the h rate cancel.
                        EXPECT_LT(voigt::norm(voigt::sub(sym_at(dy, 7), test::to_voigt(ref.h))),
                                  1e-13 * voigt::norm(d));
                    }
                }
            }
        }
    }
}

// The rate stiffness is the operator of the rate for the direction of deps: sum_j deps_j col_j
// is the stress rate, and the columns are linear in the probe (L, (L:h)h, N(h:.) parts).
TEST(HypoplasticRate, RateStiffnessReproducesTheRate) {
    Sampler smp;
    const IntegrationSettings s;
    for (const bool igs : {false, true}) {
        const HypoplasticityParams p =
            prepared(parameter_sets::hypoplasticity_karlsruhe(), igs, 1.0);
        for (int trial = 0; trial < 100; ++trial) {
            const HypoState y = smp.state(p);
            const Sym<double> d = voigt::scale(smp.direction(), 3e-4);
            const auto cols = Hypoplasticity::rate_stiffness(p, s, y, d);
            Sym<double> md = voigt::zero<double>();
            for (int j = 0; j < 6; ++j) {
                md = voigt::axpy(md, d[j], cols[j]);
            }
            const HypoState dy = Hypoplasticity::euler_increment(p, s, y, d);
            EXPECT_LT(rel_diff(md, stress_of(dy)), 1e-12);
        }
    }
}

// Isotropic compression, closed form (notes section 1): T' = -f_b f_e eps' (3 + a^2 - sqrt3 a
// f_d) 1. At e = e_i(p) the factor f_b makes the void ratio rate follow the Bauer law exactly:
// de/dp = de_i/dp = -e_i n (3/h_s) (3p/h_s)^(n-1). This holds for any roughness kappa because
// Eq. 32 uses the modified a and alpha kappa^2 in the same bracket as L and f_d.
TEST(HypoplasticRate, IsotropicCompressionAtEiFollowsBauerLawPointwise) {
    const IntegrationSettings s;
    for (const double kappa : {1.0, 0.7, 0.35}) {
        for (const auto& base :
             {parameter_sets::hypoplasticity_l4c(), parameter_sets::hypoplasticity_karlsruhe()}) {
            const HypoplasticityParams p = prepared(base, false, kappa);
            for (const double pm : {1.0, 10.0, 100.0, 1000.0, 1.0e4}) {
                const double ei = test::bauer(p, p.e_i0, pm);
                const HypoState y = test::hypo_state(test::isotropic(-pm), ei);
                const Sym<double> d = test::isotropic(-1e-6);
                const HypoState dy = Hypoplasticity::euler_increment(p, s, y, d);
                const double dp = -voigt::trace(stress_of(dy)) / 3.0;
                const double dei_dp =
                    -ei * p.n * (3.0 / p.h_s) * std::pow(3.0 * pm / p.h_s, p.n - 1.0);
                EXPECT_NEAR(dy[6] / dp, dei_dp, 1e-11 * std::fabs(dei_dp))
                    << "kappa " << kappa << " p " << pm;
                // Closed-form stress rate with f_e, f_d at e_i.
                const double sphi = std::sin(kappa * p.phi_c);
                const double a = std::sqrt(3.0) * (3.0 - sphi) / (2.0 * std::sqrt(2.0) * sphi);
                const double fd =
                    std::pow((p.e_i0 - p.e_d0) / (p.e_c0 - p.e_d0), p.alpha * kappa * kappa);
                const double fe = std::pow(p.e_c0 / p.e_i0, p.beta);
                const double fb = p.h_s / p.n * std::pow(p.e_i0 / p.e_c0, p.beta) * (1 + ei) / ei *
                                  std::pow(3 * pm / p.h_s, 1 - p.n) /
                                  (3 + a * a - a * std::sqrt(3.0) * fd);
                const double expected = -fb * fe * 1e-6 * (3 + a * a - std::sqrt(3.0) * a * fd);
                for (int i = 0; i < 3; ++i) {
                    EXPECT_NEAR(dy[i], expected, 1e-12 * std::fabs(expected));
                    EXPECT_NEAR(dy[i + 3], 0.0, 1e-14 * std::fabs(expected));
                }
            }
        }
    }
}

// The SIMD path of the rate equations agrees with the scalar path lane by lane (xsimd's
// exp/log/pow differ from libm by a few ulp only).
TEST(HypoplasticRate, BatchMatchesScalar) {
    Sampler smp;
    const IntegrationSettings s;
    for (const bool igs : {false, true}) {
        const HypoplasticityParams p = prepared(parameter_sets::hypoplasticity_l4c(), igs, 0.8);
        for (int rep = 0; rep < 20; ++rep) {
            std::vector<HypoState> ys(simd::lanes);
            std::vector<Sym<double>> ds(simd::lanes);
            for (std::size_t l = 0; l < simd::lanes; ++l) {
                ys[l] = smp.state(p);
                if (l == 0) {
                    set_sym_at(ys[l], 7, voigt::zero<double>()); // h = 0 lane
                }
                ds[l] = voigt::scale(smp.direction(), 1e-4);
            }
            const auto yb = to_batch(ys);
            const auto db = sym_batch(ds);
            const auto dyb = Hypoplasticity::euler_increment<simd::batch>(p, s, yb, db);
            const auto colsb = Hypoplasticity::rate_stiffness<simd::batch>(p, s, yb, db);
            for (std::size_t l = 0; l < simd::lanes; ++l) {
                const HypoState dy = Hypoplasticity::euler_increment(p, s, ys[l], ds[l]);
                const HypoState dyl = lane_of(dyb, l);
                EXPECT_LT(rel_diff(stress_of(dyl), stress_of(dy)), 1e-13);
                EXPECT_NEAR(dyl[6], dy[6], 1e-14 * std::fabs(dy[6]) + 1e-300);
                if (igs) {
                    EXPECT_LT(rel_diff(sym_at(dyl, 7), sym_at(dy, 7)), 1e-13);
                }
                const auto cols = Hypoplasticity::rate_stiffness(p, s, ys[l], ds[l]);
                for (int j = 0; j < 6; ++j) {
                    Sym<double> cl;
                    for (int i = 0; i < 6; ++i) {
                        cl[i] = simd::lane(colsb[j][i], l);
                    }
                    EXPECT_LT(rel_diff(cl, cols[j]), 1e-13);
                }
            }
        }
    }
}

// ------------------------------------------------------------------------------------------
// Intergranular strain stiffness: with |h| = R along a direction, the response to a 180 degree
// reversal is m_R L, to a 90 degree change m_T L, to continued loading L + N|D| (plain
// hypoplasticity); at h = 0 it is m_R L. Rate stiffness and one tiny integrated step, scalar
// and SIMD.

enum class Expected { mR_times_L, mT_times_L, hypoplastic };

struct IgsCase {
    const char* name;
    double rho;    // |h| / R
    int direction; // +1 along h, -1 reversed, 0 perpendicular
    Expected expected;
};

TEST(IntergranularStrain, StiffnessMultipliersAtReversals) {
    Sampler smp;
    const IntegrationSettings s;
    const IgsCase cases[] = {{"reversal 180", 1.0, -1, Expected::mR_times_L},
                             {"change 90", 1.0, 0, Expected::mT_times_L},
                             {"h = 0", 0.0, 0, Expected::mR_times_L},
                             {"continued loading", 1.0, +1, Expected::hypoplastic}};
    for (const auto& base :
         {parameter_sets::hypoplasticity_l4c(), parameter_sets::hypoplasticity_karlsruhe()}) {
        const HypoplasticityParams p = prepared(base, true);
        HypoplasticityParams p_plain = prepared(base, false);
        for (const IgsCase& c : cases) {
            const double factor = c.expected == Expected::mR_times_L ? p.m_R : p.m_T;
            std::vector<HypoState> ys(simd::lanes);
            std::vector<Sym<double>> ds(simd::lanes);
            std::vector<Sym<double>> expected(simd::lanes);
            for (std::size_t l = 0; l < simd::lanes; ++l) {
                const Sym<double> sig = smp.stress();
                const Sym<double> hdir = smp.direction();
                Sym<double> d = hdir;
                if (c.direction == -1) {
                    d = voigt::scale(hdir, -1.0);
                } else if (c.direction == 0) {
                    // Random direction made perpendicular to h (a 90 degree change).
                    Sym<double> r = smp.direction();
                    r = voigt::axpy(r, -voigt::ddot(r, hdir), hdir);
                    d = voigt::scale(r, 1.0 / voigt::norm(r));
                }
                ys[l] =
                    test::hypo_state(sig, smp.void_ratio(p, sig), voigt::scale(hdir, c.rho * p.R));
                ds[l] = d;
                const ReferenceRate plain = reference_rate(p_plain, test::to_matrix(sig), ys[l][6],
                                                           Mat3{}, test::to_matrix(d));
                if (c.expected == Expected::hypoplastic) {
                    expected[l] = test::to_voigt(plain.stress); // L:D + N|D|, |D| = 1
                } else {
                    // L:D alone = reference rate minus N|D| (rate at +D and -D: L odd, N even).
                    const ReferenceRate minus =
                        reference_rate(p_plain, test::to_matrix(sig), ys[l][6], Mat3{},
                                       test::to_matrix(voigt::scale(d, -1.0)));
                    const Sym<double> LD = voigt::scale(
                        voigt::sub(test::to_voigt(plain.stress), test::to_voigt(minus.stress)),
                        0.5);
                    expected[l] = voigt::scale(LD, factor);
                }
            }
            // Rate stiffness, scalar and batch.
            const auto yb = to_batch(ys);
            const auto db = sym_batch(ds);
            const auto colsb = Hypoplasticity::rate_stiffness<simd::batch>(p, s, yb, db);
            for (std::size_t l = 0; l < simd::lanes; ++l) {
                const auto cols = Hypoplasticity::rate_stiffness(p, s, ys[l], ds[l]);
                Sym<double> md = voigt::zero<double>(), mdb = voigt::zero<double>();
                for (int j = 0; j < 6; ++j) {
                    md = voigt::axpy(md, ds[l][j], cols[j]);
                    Sym<double> cl;
                    for (int i = 0; i < 6; ++i) {
                        cl[i] = simd::lane(colsb[j][i], l);
                    }
                    mdb = voigt::axpy(mdb, ds[l][j], cl);
                }
                EXPECT_LT(rel_diff(md, expected[l]), 1e-12) << c.name;
                EXPECT_LT(rel_diff(mdb, expected[l]), 1e-12) << c.name << " (SIMD)";
            }
            // A tiny integrated step: |deps| = 1e-5 R changes h, e and T by a relative 1e-5 at
            // most, so the secant stiffness equals the rate stiffness to that order.
            const double size = 1e-5 * p.R;
            std::vector<Sym<double>> small(simd::lanes);
            for (std::size_t l = 0; l < simd::lanes; ++l) {
                small[l] = voigt::scale(ds[l], size);
            }
            auto ybs = to_batch(ys);
            UpdateStats<simd::batch> stb;
            material_update<Hypoplasticity, simd::batch>(p, s, SubstepControl<simd::batch>{}, ybs,
                                                         sym_batch(small), stb);
            for (std::size_t l = 0; l < simd::lanes; ++l) {
                HypoState y = ys[l];
                const auto st = test::strain_step(p, s, y, small[l]);
                ASSERT_EQ(st.status, lane_status::ok);
                const Sym<double> secant =
                    voigt::scale(voigt::sub(stress_of(y), stress_of(ys[l])), 1.0 / size);
                const Sym<double> secant_b = voigt::scale(
                    voigt::sub(stress_of(lane_of(ybs, l)), stress_of(ys[l])), 1.0 / size);
                EXPECT_LT(rel_diff(secant, expected[l]), 1e-4) << c.name;
                EXPECT_LT(rel_diff(secant_b, expected[l]), 1e-4) << c.name << " (SIMD)";
            }
        }
    }
}

// ------------------------------------------------------------------------------------------
// Objectivity / isotropy: rotating stress, h and the strain increment rotates the result.

TEST(HypoplasticIsotropy, RotatedInputGivesRotatedOutput) {
    Sampler smp;
    IntegrationSettings s;
    s.tolerance = 1e-5;
    for (const bool igs : {false, true}) {
        const HypoplasticityParams p = prepared(parameter_sets::hypoplasticity_karlsruhe(), igs);
        double worst = 0.0;
        for (int trial = 0; trial < 40; ++trial) {
            const HypoState y0 = smp.state(p);
            const Sym<double> d = voigt::scale(smp.direction(), smp.uniform(1e-5, 2e-3));
            const Mat3 Q = smp.rotation();
            HypoState y = y0;
            ASSERT_GE(test::strain_step(p, s, y, d).status, lane_status::ok);
            HypoState yr = test::hypo_state(test::rotate(Q, stress_of(y0)), y0[6],
                                            test::rotate(Q, sym_at(y0, 7)));
            ASSERT_GE(test::strain_step(p, s, yr, test::rotate(Q, d)).status, lane_status::ok);
            const double ds = rel_diff(stress_of(yr), test::rotate(Q, stress_of(y)));
            worst = std::max(worst, ds);
            // The substep sequence is rotation invariant up to round-off in the error norms;
            // agreement is to round-off unless an accept decision flips (then within tolerance).
            EXPECT_LT(ds, 1e-9) << "trial " << trial;
            EXPECT_NEAR(yr[6], y[6], 1e-12);
            if (igs) {
                EXPECT_LT(voigt::norm(voigt::sub(sym_at(yr, 7), test::rotate(Q, sym_at(y, 7)))),
                          1e-9 * p.R);
            }
        }
        RecordProperty(igs ? "worst_rotation_error_igs" : "worst_rotation_error", sci(worst));
    }
}

// ------------------------------------------------------------------------------------------
// Bauer compression law under isotropic compression.
//
// f_b is derived so that e_i(p) is an invariant curve of isotropic compression: a sample at
// e = e_i(p0) stays on e_i(p) (checked tightly, within the integration tolerance). e_c(p) and
// e_d(p) are NOT invariant curves of isotropic compression (they are reached by monotonic and
// by cyclic shearing): a sample started on them drifts off them at a rate the rate equations
// fix (log_slope_ratio below); for L4C it moves towards e_i, i.e. the density index
// r = (e - e_d)/(e_i - e_d) grows monotonically, but by uniqueness of the solution through the
// invariant curve e_i it never reaches 1. For Karlsruhe sand (beta = 0.32) the drift from e_c
// is tiny and changes sign with pressure. That is what the tests assert for those starts.

struct CompressionRun {
    double max_dev_from_ei = 0.0;
    double r_first = 0.0, r_last = 0.0;
    bool r_monotonic = true;
    double max_r = 0.0;
    double min_r = 1.0;
    double p_last = 0.0;
    double e_over_ec_last = 0.0;
};

CompressionRun isotropic_compression(const HypoplasticityParams& p, const IntegrationSettings& s,
                                     double e0, const Sym<double>& h0, int steps, double dv) {
    HypoState y = test::hypo_state(test::isotropic(-10.0), e0, h0);
    CompressionRun run;
    auto index = [&](const HypoState& st) {
        const double pm = mean_pressure(stress_of(st));
        const double ei = test::bauer(p, p.e_i0, pm), ed = test::bauer(p, p.e_d0, pm);
        return (st[6] - ed) / (ei - ed);
    };
    run.r_first = index(y);
    double r_prev = run.r_first;
    for (int k = 0; k < steps; ++k) {
        const auto st = test::strain_step(p, s, y, test::isotropic(-dv / 3.0));
        EXPECT_EQ(st.status, lane_status::ok);
        const double pm = mean_pressure(stress_of(y));
        run.max_dev_from_ei =
            std::max(run.max_dev_from_ei, std::fabs(y[6] / test::bauer(p, p.e_i0, pm) - 1.0));
        const double r = index(y);
        run.r_monotonic = run.r_monotonic && (r >= r_prev - 1e-9);
        run.max_r = std::max(run.max_r, r);
        run.min_r = std::min(run.min_r, r);
        r_prev = r;
        // Stress stays isotropic (isotropy of the model).
        EXPECT_NEAR(y[0], y[1], 1e-10 * pm);
        EXPECT_NEAR(y[0], y[2], 1e-10 * pm);
        EXPECT_NEAR(y[3], 0.0, 1e-10 * pm);
    }
    run.r_last = r_prev;
    run.p_last = mean_pressure(stress_of(y));
    run.e_over_ec_last = y[6] / test::bauer(p, p.e_c0, run.p_last);
    return run;
}

TEST(BauerLaw, CompressionFromEiFollowsEi) {
    IntegrationSettings s;
    s.tolerance = 1e-6;
    for (const auto& base :
         {parameter_sets::hypoplasticity_l4c(), parameter_sets::hypoplasticity_karlsruhe()}) {
        for (const double kappa : {1.0, 0.5}) {
            const HypoplasticityParams p = prepared(base, false, kappa);
            const double e0 = test::bauer(p, p.e_i0, 10.0);
            // 10 kPa -> several MPa (volumetric strain 0.15).
            const CompressionRun run = isotropic_compression(p, s, e0, {}, 300, 5e-4);
            EXPECT_GT(run.p_last, 1000.0);
            EXPECT_LT(run.max_dev_from_ei, 10.0 * s.tolerance) << "kappa " << kappa;
            RecordProperty("max_e_over_ei_minus_1", sci(run.max_dev_from_ei));

            // With intergranular strain fully mobilised along the compression direction
            // (|h| = R, h parallel to D) the model is plain hypoplasticity: same curve.
            const HypoplasticityParams pi = prepared(base, true, kappa);
            const CompressionRun run_igs = isotropic_compression(
                pi, s, e0, test::isotropic(-pi.R / std::sqrt(3.0)), 300, 5e-4);
            EXPECT_LT(run_igs.max_dev_from_ei, 10.0 * s.tolerance);
        }
    }
}

// Ratio of the log-slopes (d ln e/dp) / (d ln e_x/dp) of isotropic compression at e = e_x(p),
// from the rate equations with f_b of Eq. 32:
//   R_x = (1+e_x)/e_x * e_i/(1+e_i) * (e_x0/e_i0)^beta * B_i / B_x,
//   B_x = 3 + a^2 - sqrt3 a f_d(e_x),  f_d(e_i) = ((e_i0-e_d0)/(e_c0-e_d0))^alpha, f_d(e_c) = 1,
//   f_d(e_d) = 0.
// R_i = 1 (e_i is invariant); R_c and R_d differ from 1, so e_c and e_d are not followed.
double log_slope_ratio(const HypoplasticityParams& p, double e_x0, double fd_x, double pm) {
    const double sphi = std::sin(p.roughness * p.phi_c);
    const double a = std::sqrt(3.0) * (3.0 - sphi) / (2.0 * std::sqrt(2.0) * sphi);
    const double alpha = p.alpha * p.roughness * p.roughness;
    const double fd_i = std::pow((p.e_i0 - p.e_d0) / (p.e_c0 - p.e_d0), alpha);
    const double ex = test::bauer(p, e_x0, pm), ei = test::bauer(p, p.e_i0, pm);
    const double Bi = 3.0 + a * a - std::sqrt(3.0) * a * fd_i;
    const double Bx = 3.0 + a * a - std::sqrt(3.0) * a * fd_x;
    return (1.0 + ex) / ex * ei / (1.0 + ei) * std::pow(e_x0 / p.e_i0, p.beta) * Bi / Bx;
}

TEST(BauerLaw, EcAndEdAreNotInvariantUnderIsotropicCompression) {
    const IntegrationSettings s;
    for (const auto& base :
         {parameter_sets::hypoplasticity_l4c(), parameter_sets::hypoplasticity_karlsruhe()}) {
        const HypoplasticityParams p = prepared(base, false);
        for (const double pm : {10.0, 1000.0, 1.0e5}) {
            struct Curve {
                double e_x0, fd;
            };
            for (const Curve c : {Curve{p.e_c0, 1.0}, Curve{p.e_d0, 0.0}}) {
                const double ex = test::bauer(p, c.e_x0, pm);
                const HypoState y = test::hypo_state(test::isotropic(-pm), ex);
                const HypoState dy =
                    Hypoplasticity::euler_increment(p, s, y, test::isotropic(-1e-7));
                const double dlne_dp = dy[6] / ex / (-voigt::trace(stress_of(dy)) / 3.0);
                const double dlnex_dp =
                    -p.n * (3.0 / p.h_s) * std::pow(3.0 * pm / p.h_s, p.n - 1.0);
                const double expected = log_slope_ratio(p, c.e_x0, c.fd, pm);
                EXPECT_NEAR(dlne_dp / dlnex_dp, expected, 1e-11 * expected);
            }
        }
    }
    // For L4C (beta = 1.2) the ratio at e_c is far from 1: e_c is clearly not followed.
    const HypoplasticityParams l4c = prepared(parameter_sets::hypoplasticity_l4c(), false);
    EXPECT_LT(log_slope_ratio(l4c, l4c.e_c0, 1.0, 10.0), 0.9);
}

// Integrated from e_c and e_d: the state leaves the start curve as R_x predicts but stays in
// the admissible range e_d(p) <= e <= e_i(p): it cannot cross the invariant curve e_i
// (uniqueness) and at e = e_d the void ratio falls more slowly than e_d (R_d < 1).
TEST(BauerLaw, CompressionFromEcAndEdStaysBetweenEdAndEi) {
    IntegrationSettings s;
    s.tolerance = 1e-6;
    for (const auto& base :
         {parameter_sets::hypoplasticity_l4c(), parameter_sets::hypoplasticity_karlsruhe()}) {
        const HypoplasticityParams p = prepared(base, false);
        EXPECT_LT(log_slope_ratio(p, p.e_d0, 0.0, 10.0), 1.0);
        for (const double e_x0 : {p.e_c0, p.e_d0}) {
            const double e0 = test::bauer(p, e_x0, 10.0);
            const CompressionRun run = isotropic_compression(p, s, e0, {}, 300, 5e-4);
            EXPECT_GE(run.min_r, 0.0);
            EXPECT_LT(run.max_r, 1.0);
            EXPECT_GT(run.p_last, 1000.0);
        }
    }
    // L4C from e_c: R_c < 1, so e/e_c grows (towards e_i); by > 1 % over 10 kPa -> MPa.
    const HypoplasticityParams p = prepared(parameter_sets::hypoplasticity_l4c(), false);
    const CompressionRun run =
        isotropic_compression(p, s, test::bauer(p, p.e_c0, 10.0), {}, 300, 5e-4);
    EXPECT_GT(run.e_over_ec_last, 1.01);
    EXPECT_TRUE(run.r_monotonic);
}

// ------------------------------------------------------------------------------------------
// Critical state under monotonic shearing: q/p -> M_c = 6 sin(phi)/(3 - sin(phi)) in triaxial
// compression, the mobilised Matsuoka-Nakai angle -> phi for any Lode angle, e -> e_c(p).
// Asymptotic states: the deviation decays roughly like exp(-1.5 eps) for these parameters, so
// the runs shear to 10-12 (small-strain theory, no geometry). The discrete solution settles
// within ~0.5 tolerance of the critical state (near the stationary state the step controller
// grows the substep to the stability limit of Heun, where an oscillation of relative size ~tol
// passes the error test), so the runs use tolerance 1e-6 and assert 2e-6.

TEST(CriticalState, DrainedTriaxialCompressionWithoutIntergranularStrain) {
    IntegrationSettings s;
    s.tolerance = 1e-6;
    for (const auto& base :
         {parameter_sets::hypoplasticity_l4c(), parameter_sets::hypoplasticity_karlsruhe()}) {
        const HypoplasticityParams p = prepared(base, false);
        const double Mc = test::critical_ratio_compression(p.phi_c);
        for (const double density : {0.85, 1.05}) { // dense (dilates) and loose (contracts)
            HypoState y =
                test::hypo_state(test::isotropic(-100.0), density * test::bauer(p, p.e_c0, 100.0));
            const auto r = test::drained_triaxial(p, s, y, 10.0, 500);
            ASSERT_TRUE(r.ok) << "Newton failed at step " << r.steps;
            const double pm = mean_pressure(stress_of(y));
            const double q = test::deviatoric_q(stress_of(y));
            EXPECT_NEAR(q / pm, Mc, 2e-6 * Mc) << "density " << density;
            EXPECT_NEAR(y[6] / test::bauer(p, p.e_c0, pm), 1.0, 2e-6) << "density " << density;
            // Lateral stress held, axial stress is the larger compression.
            EXPECT_NEAR(y[1], -100.0, 1e-6);
            EXPECT_NEAR(y[2], -100.0, 1e-6);
            EXPECT_NEAR(pm, 300.0 / (3.0 - Mc), 1e-4); // p = 3 sigma_3 / (3 - M_c) at q = M_c p
        }
    }
}

// Isochoric (undrained) triaxial compression and isochoric simple shear: e is constant, so the
// critical state is reached at p_c with e_c(p_c) = e, p_c = h_s/3 (ln(e_c0/e))^(1/n).
// p approaches p_c more slowly than the stress ratio approaches its limit, the more so the
// smaller the friction angle (kappa phi_c): the rough cases shear further.
struct IsochoricCase {
    bool igs;
    bool simple_shear;
    double kappa;
    double strain = 12.0; // eps_11 (triaxial) or eps_12 (simple shear), steps of 0.02
};

void check_isochoric(const HypoplasticityParams& base, const IsochoricCase& c) {
    const HypoplasticityParams p = prepared(base, c.igs, c.kappa);
    IntegrationSettings s;
    s.tolerance = 1e-6;
    const double phi = c.kappa * p.phi_c;
    for (const double pc_over_p0 : {0.5, 2.0}) { // loose (p falls) and dense (p rises)
        const double e = test::bauer(p, p.e_c0, 100.0 * pc_over_p0);
        const double pc = p.h_s / 3.0 * std::pow(std::log(p.e_c0 / e), 1.0 / p.n);
        HypoState y = test::hypo_state(test::isotropic(-100.0), e);
        const Sym<double> d = c.simple_shear ? Sym<double>{0.0, 0.0, 0.0, 0.02, 0.0, 0.0}
                                             : Sym<double>{-0.02, 0.01, 0.01, 0.0, 0.0, 0.0};
        const int steps = static_cast<int>(c.strain / 0.02);
        for (int k = 0; k < steps; ++k) {
            const auto st = test::strain_step(p, s, y, d);
            ASSERT_EQ(st.status, lane_status::ok) << "step " << k;
        }
        const double pm = mean_pressure(stress_of(y));
        EXPECT_NEAR(y[6], e, 1e-12);
        EXPECT_NEAR(pm / pc, 1.0, 2e-6) << "igs " << c.igs << " shear " << c.simple_shear;
        EXPECT_NEAR(test::matsuoka_nakai_angle(stress_of(y)), phi, 2e-6 * phi);
        if (!c.simple_shear) {
            const double Mc = test::critical_ratio_compression(phi);
            EXPECT_NEAR(test::deviatoric_q(stress_of(y)) / pm, Mc, 2e-6 * Mc);
        }
    }
}

TEST(CriticalState, IsochoricTriaxialAndSimpleShear) {
    for (const auto& base :
         {parameter_sets::hypoplasticity_l4c(), parameter_sets::hypoplasticity_karlsruhe()}) {
        for (const bool igs : {false, true}) {
            for (const bool shear : {false, true}) {
                check_isochoric(base, {igs, shear, 1.0});
            }
        }
    }
}

// With roughness kappa < 1 the critical stress ratio is that of kappa phi_c (Eq. 30); e_c(p)
// is unchanged.
TEST(CriticalState, RoughnessScalesTheCriticalFrictionAngle) {
    check_isochoric(parameter_sets::hypoplasticity_karlsruhe(), {false, false, 0.6, 40.0});
    check_isochoric(parameter_sets::hypoplasticity_karlsruhe(), {true, true, 0.6, 40.0});
    // Drained: the deviation decays like exp(-0.33 eps) at kappa = 0.6 (exp(-0.06 eps) at
    // kappa = 0.35, see long_test_critical_state.cpp).
    const double kappa = 0.6;
    const HypoplasticityParams p = prepared(parameter_sets::hypoplasticity_l4c(), false, kappa);
    IntegrationSettings s;
    s.tolerance = 1e-6;
    HypoState y = test::hypo_state(test::isotropic(-100.0), test::bauer(p, p.e_c0, 100.0));
    ASSERT_TRUE(test::drained_triaxial(p, s, y, 30.0, 1500).ok);
    const double pm = mean_pressure(stress_of(y));
    const double Mk = test::critical_ratio_compression(kappa * p.phi_c);
    EXPECT_NEAR(test::deviatoric_q(stress_of(y)) / pm, Mk, 2e-6 * Mk);
    EXPECT_NEAR(y[6] / test::bauer(p, p.e_c0, pm), 1.0, 2e-6);
    // Far from the continuum value: the test would catch kappa being ignored.
    EXPECT_GT(test::critical_ratio_compression(p.phi_c) - Mk, 0.3);
}

// Section 3 of the notes: the roughness modification is exactly an unmodified model with
// phi_c' = kappa phi_c and alpha' = kappa^2 alpha.
TEST(CriticalState, RoughnessEqualsModifiedFrictionAngleAndAlpha) {
    Sampler smp;
    const IntegrationSettings s;
    const double kappa = 0.55;
    const HypoplasticityParams rough =
        prepared(parameter_sets::hypoplasticity_karlsruhe(), true, kappa);
    HypoplasticityParams plain = parameter_sets::hypoplasticity_karlsruhe();
    plain.phi_c *= kappa;
    plain.alpha *= kappa * kappa;
    plain = prepared(plain, true, 1.0);
    for (int trial = 0; trial < 50; ++trial) {
        const HypoState y = smp.state(rough);
        const Sym<double> d = voigt::scale(smp.direction(), 1e-4);
        const HypoState a = Hypoplasticity::euler_increment(rough, s, y, d);
        const HypoState b = Hypoplasticity::euler_increment(plain, s, y, d);
        EXPECT_LT(rel_diff(stress_of(a), stress_of(b)), 1e-13);
    }
}

} // namespace
} // namespace ifsim
