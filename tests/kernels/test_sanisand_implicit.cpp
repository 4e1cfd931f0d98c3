// Backward-Euler steps of Sanisand (kernels/sanisand_implicit.hpp): first-order convergence to
// the explicit reference on a shear path at 100 and 3 kPa, the end state on the cone, the
// closed-form elastic step, continuity across a load reversal, the dense solver against a
// known solution, and every SIMD lane against the scalar path.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "kernels/dense_solve.hpp"
#include "kernels/material_update.hpp"
#include "kernels/parameter_sets.hpp"
#include "kernels/sanisand.hpp"
#include "tests/kernels/sanisand_test_support.hpp"

using namespace ifsim;

namespace {

using namespace sanisand_test;

IntegrationSettings implicit_settings() {
    IntegrationSettings s;
    s.backward_euler = true;
    return s;
}

UpdateStats<double> step(const SanisandParams& P, const IntegrationSettings& s, Y& y,
                         const Sym<double>& de) {
    UpdateStats<double> st;
    material_update<Sanisand, double>(P, s, SubstepControl<double>{}, y, de, st);
    return st;
}

// Shear in 12 with a slight extension in 22 to a total shear strain of 1e-2 in n calls.
Y shear_path(const SanisandParams& P, const IntegrationSettings& s, double p0, int n,
             int* not_ok = nullptr) {
    Y y = Sanisand::initial_state({-p0, -0.5 * p0, -0.5 * p0, 0.0, 0.0, 0.0}, 0.65);
    const double total = 1.0e-2;
    for (int k = 0; k < n; ++k) {
        const Sym<double> de{0.0, -0.1 * total / n, 0.0, total / n, 0.0, 0.0};
        const auto st = step(P, s, y, de);
        if (not_ok != nullptr && st.status < 0.5) {
            ++*not_ok;
        }
    }
    return y;
}

double stress_error(const Y& a, const Y& ref) {
    double d = 0.0, n = 0.0;
    for (int i = 0; i < 6; ++i) {
        d += (a[i] - ref[i]) * (a[i] - ref[i]);
        n += ref[i] * ref[i];
    }
    return std::sqrt(d / n);
}

} // namespace

TEST(DenseSolve, SolvesAPivotingSystemAndFlagsASingularOne) {
    // zero diagonal: only partial pivoting solves it
    DenseMatrix<double, 3> A{{{0.0, 2.0, 1.0}, {1.0, 0.0, 3.0}, {4.0, 1.0, 0.0}}};
    const std::array<double, 3> x{1.5, -2.0, 0.25};
    DenseVector<double, 3> b{};
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) {
            b[r] += A[r][c] * x[c];
        }
    }
    EXPECT_TRUE((dense_solve<double, 3>(A, b)));
    for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(b[i], x[i], 1e-14);
    }
    DenseMatrix<double, 3> S{{{1.0, 2.0, 3.0}, {2.0, 4.0, 6.0}, {0.0, 1.0, 1.0}}};
    DenseVector<double, 3> bs{1.0, 2.0, 3.0};
    EXPECT_FALSE((dense_solve<double, 3>(S, bs)));
    EXPECT_EQ(bs[0], 0.0);
}

// Backward Euler is first order: ten times the calls, about a tenth of the error, against the
// explicit scheme at a tight tolerance. At 3 kPa (G/p large) and at 100 kPa.
TEST(SanisandImplicit, ConvergesAtFirstOrderToTheExplicitReference) {
    const auto P = karlsruhe(0.9);
    IntegrationSettings tight;
    tight.scheme = IntegrationScheme::heun;
    tight.tolerance = 1.0e-6;
    for (double p0 : {100.0, 3.0}) {
        const Y ref = shear_path(P, tight, p0, 1000);
        int not_ok = 0;
        const double e10 = stress_error(shear_path(P, implicit_settings(), p0, 10, &not_ok), ref);
        const double e100 = stress_error(shear_path(P, implicit_settings(), p0, 100, &not_ok), ref);
        const double e1000 =
            stress_error(shear_path(P, implicit_settings(), p0, 1000, &not_ok), ref);
        EXPECT_EQ(not_ok, 0) << p0;
        EXPECT_LT(e10, 0.05) << p0;
        EXPECT_LT(e100, 0.3 * e10) << p0;
        EXPECT_LT(e1000, 0.3 * e100 + 1e-5) << p0;
        EXPECT_LT(e1000, 2e-3) << p0;
    }
}

// A plastic step ends on the cone with alpha and z deviatoric; the void ratio follows the
// volumetric strain exactly.
TEST(SanisandImplicit, PlasticStepEndsOnTheCone) {
    const auto P = karlsruhe();
    Y y = Sanisand::initial_state({-50.0, -30.0, -35.0, 4.0, 0.0, -2.0}, 0.7);
    const Sym<double> de{-2.0e-3, 1.0e-3, 0.5e-3, 3.0e-3, -1.0e-3, 0.5e-3};
    const double ev = voigt::trace(de);
    const auto st = step(P, implicit_settings(), y, de);
    EXPECT_EQ(st.status, lane_status::ok);
    EXPECT_NEAR(sanisand::yield_ratio(P, {}, y), 0.0, 1e-10);
    EXPECT_NEAR(y[6], (1.0 + 0.7) * std::exp(ev) - 1.0, 1e-14);
    for (int offset : {Sanisand::alpha_index, Sanisand::z_index, Sanisand::alpha_in_index}) {
        EXPECT_NEAR(voigt::trace(sym_at(y, offset)), 0.0, 1e-14) << offset;
    }
}

// Inside the cone the step is the closed-form end-state hypoelastic law:
// p = p_n + K_hat sqrt(p) deps_v (compression positive), s = s_n + 2 G_hat sqrt(p) de.
TEST(SanisandImplicit, ElasticStepIsTheClosedFormHypoelasticity) {
    const auto P = karlsruhe();
    const Y y0 = Sanisand::initial_state({-120.0, -70.0, -60.0, 5.0, -3.0, 2.0}, 0.8);
    const Sym<double> de{-2.0e-5, 1.5e-5, -0.5e-5, 1.0e-5, 0.5e-5, -0.8e-5};
    Y y = y0;
    const auto st = step(P, implicit_settings(), y, de);
    EXPECT_EQ(st.status, lane_status::ok);
    const double e1 = 1.8 * std::exp(voigt::trace(de)) - 1.0;
    const double G_hat = P.G0 * P.p_a * (2.97 - e1) * (2.97 - e1) / (1.0 + e1) / std::sqrt(P.p_a);
    const double p = mean_pressure(stress_of(y));
    const double p0 = mean_pressure(stress_of(y0));
    EXPECT_NEAR(p, p0 - P.K_over_G * G_hat * std::sqrt(p) * voigt::trace(de), 1e-10);
    const Sym<double> dev = voigt::deviator(de);
    for (int i = 3; i < 6; ++i) {
        EXPECT_NEAR(y[i] - y0[i], 2.0 * G_hat * std::sqrt(p) * dev[i], 1e-10) << i;
    }
    for (int i = 7; i < Sanisand::n_state; ++i) {
        EXPECT_NEAR(y[i], y0[i], 1e-15) << i; // alpha, z, alpha_in (traces removed again)
    }
    EXPECT_LT(sanisand::yield_ratio(P, {}, y), 0.0);
}

// The alpha_in reset in its end-normal form makes the result continuous in the strain
// increment: after loading in +12, increments from -a to +a in 12 change the stress by an
// amount bounded by a Lipschitz constant of the elastic stiffness' order, without a jump at the
// switch of the reversal test.
TEST(SanisandImplicit, ResultIsContinuousAcrossALoadReversal) {
    const auto P = karlsruhe();
    Y y0 = Sanisand::initial_state({-60.0, -60.0, -60.0, 0.0, 0.0, 0.0}, 0.7);
    for (int k = 0; k < 20; ++k) {
        step(P, implicit_settings(), y0, Sym<double>{0.0, 0.0, 0.0, 2.0e-4, 0.0, 0.0});
    }
    const double G = P.G0 * P.p_a * 5.3 / 1.7 * std::sqrt(2.0); // above G at these states
    double prev = 0.0;
    for (int k = -40; k <= 40; ++k) {
        const double d = 1.0e-6 * k;
        Y y = y0;
        const auto st = step(P, implicit_settings(), y, Sym<double>{0.0, 0.0, 0.0, d, 0.0, 0.0});
        ASSERT_EQ(st.status, lane_status::ok) << k;
        if (k > -40) {
            EXPECT_LT(std::abs(y[3] - prev), 2.0 * G * 1.0e-6 * 1.5) << k;
        }
        prev = y[3];
    }
}

// Each SIMD lane equals the scalar path to round-off (xsimd's exp and pow differ from the C
// library's in the last bits) with the same number of steps; the increments differ per lane, so
// lanes converge after different numbers of iterations.
TEST(SanisandImplicit, SimdLanesEqualTheScalarPath) {
    const auto P = karlsruhe(0.9);
    std::array<Y, W> ys;
    std::array<Sym<double>, W> ds;
    YB yb;
    Sym<Batch> db;
    for (std::size_t l = 0; l < W; ++l) {
        const double p = 2.0 + 20.0 * double(l);
        ys[l] = Sanisand::initial_state({-p, -0.6 * p, -0.8 * p, 0.1 * p, 0.0, 0.0}, 0.66);
        const double a = 1.0e-4 * std::pow(4.0, double(l % 4));
        ds[l] = {0.2 * a, -0.3 * a, 0.0, a * (l % 2 == 0 ? 1.0 : -1.0), 0.1 * a, 0.0};
    }
    for (int k = 0; k < Sanisand::n_state; ++k) {
        alignas(64) double buf[W];
        for (std::size_t l = 0; l < W; ++l) {
            buf[l] = ys[l][k];
        }
        yb[k] = Batch::load_aligned(buf);
    }
    for (int k = 0; k < 6; ++k) {
        alignas(64) double buf[W];
        for (std::size_t l = 0; l < W; ++l) {
            buf[l] = ds[l][k];
        }
        db[k] = Batch::load_aligned(buf);
    }
    UpdateStats<Batch> sb;
    material_update<Sanisand, Batch>(P, implicit_settings(), SubstepControl<Batch>{}, yb, db, sb);
    for (std::size_t l = 0; l < W; ++l) {
        Y y = ys[l];
        const auto st = step(P, implicit_settings(), y, ds[l]);
        EXPECT_EQ(simd::lane(sb.status, l), st.status) << l;
        EXPECT_EQ(simd::lane(sb.substeps, l), st.substeps) << l;
        for (int k = 0; k < Sanisand::n_state; ++k) {
            EXPECT_NEAR(simd::lane(yb[k], l), y[k], 1e-9 * (1.0 + std::fabs(y[k])))
                << l << " " << k;
        }
    }
}
