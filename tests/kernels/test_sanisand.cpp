// Sanisand 2004 (Dafalias & Manzari 2004) with the roughness factor of Staubach et al. (2022):
// hypoelasticity inside the cone against closed forms, consistency and step-size independence,
// critical state in drained and undrained triaxial compression and extension, fabric only under
// dilation, cyclic liquefaction, Eq. 33, hard inputs, the rate stiffness against a finite
// difference, and the SIMD path against the scalar path.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "kernels/material_update.hpp"
#include "kernels/parameter_sets.hpp"
#include "kernels/sanisand.hpp"
#include "tests/kernels/sanisand_test_support.hpp"

using namespace ifsim;

namespace {

using namespace sanisand_test;

Sym<double> isotropic(double v) {
    return voigt::scale(voigt::identity<double>(), v);
}

// Compression positive invariants of the flat state.
double p_of(const Y& y) {
    return mean_pressure(stress_of(y));
}
// Triaxial deviator q = sigma_axial - sigma_lateral (compression positive, axial = 11).
double q_of(const Y& y) {
    return y[2] - y[0];
}
double e_crit(const SanisandParams& P, double p) {
    return P.e0 - P.lambda_c * std::pow(p / P.p_a, P.xi);
}
double psi_of(const SanisandParams& P, const Y& y) {
    return y[6] - e_crit(P, p_of(y));
}
// Mean pressure at the critical state for void ratio e: e = e0 - lambda_c (p/p_a)^xi.
double p_critical(const SanisandParams& P, double e) {
    return P.p_a * std::pow((P.e0 - e) / P.lambda_c, 1.0 / P.xi);
}
// Eq. 33 from the set's M_c and kappa.
double eq33_Mc(double Mc, double kappa) {
    const double s = std::sin(kappa * std::asin(3.0 * Mc / (6.0 + Mc)));
    return 6.0 * s / (3.0 - s);
}
double eq33_Me(double Mc, double kappa) {
    const double s = std::sin(kappa * std::asin(3.0 * Mc / (6.0 + Mc)));
    return 6.0 * s / (3.0 + s);
}

// Isochoric (undrained) triaxial strain increment; d > 0 compresses axially.
Sym<double> isochoric(double d) {
    return {-d, 0.5 * d, 0.5 * d, 0.0, 0.0, 0.0};
}

UpdateStats<double> step(const SanisandParams& P, Y& y, const Sym<double>& de,
                         const IntegrationSettings& s = {}, const SubstepControl<double>& c = {}) {
    UpdateStats<double> st;
    material_update<Sanisand, double>(P, s, c, y, de, st);
    return st;
}

bool all_finite(const Y& y) {
    for (double v : y) {
        if (!std::isfinite(v)) {
            return false;
        }
    }
    return true;
}

// Drained triaxial step: axial strain increment -d (compression), lateral stresses held at
// -sigma_lat by a Newton iteration on the lateral strain (equal in 22 and 33 by symmetry) with the
// rate stiffness as tangent.
UpdateStats<double> drained_step(const SanisandParams& P, Y& y, double d, double sigma_lat,
                                 const IntegrationSettings& s = {}) {
    const Y y0 = y;
    Sym<double> de{-d, 0.5 * d, 0.5 * d, 0.0, 0.0, 0.0};
    UpdateStats<double> st;
    for (int it = 0; it < 40; ++it) {
        y = y0;
        st = step(P, y, de, s);
        const double r = y[1] + sigma_lat;
        if (std::fabs(r) < 1.0e-9 * sigma_lat) {
            EXPECT_EQ(y[1], y[2]);
            return st;
        }
        const auto K = Sanisand::rate_stiffness(P, s, y0, de);
        const double dx = r / (K[1][1] + K[2][1]);
        de[1] -= dx;
        de[2] -= dx;
    }
    ADD_FAILURE() << "drained Newton did not converge: " << y[1] + sigma_lat;
    return st;
}

YB pack(const std::array<Y, W>& ys) {
    return pack_states(ys);
}
Sym<Batch> pack(const std::array<Sym<double>, W>& ds) {
    return pack_increments(ds);
}
Y lane_of(const YB& yb, std::size_t l) {
    Y y;
    for (int k = 0; k < Sanisand::n_state; ++k) {
        y[k] = simd::lane(yb[k], l);
    }
    return y;
}

} // namespace

TEST(SanisandParams, TableFourAndRoughnessEquations) {
    const auto p = parameter_sets::sanisand("karlsruhe-sand");
    ASSERT_TRUE(p.has_value());
    EXPECT_FALSE(parameter_sets::sanisand("l4c").has_value());
    EXPECT_DOUBLE_EQ(p->M_c_eff, 1.3); // kappa = 1: the set's values as they are
    EXPECT_DOUBLE_EQ(p->c_eff, 0.88);
    EXPECT_DOUBLE_EQ(p->n_b_eff, 1.3);
    EXPECT_DOUBLE_EQ(p->A0_eff, 0.8);
    EXPECT_NEAR(p->K_over_G, 2.0 * 1.05 / (3.0 * 0.9), 1e-15);

    const auto half = karlsruhe(0.5);
    EXPECT_NEAR(half.M_c_eff, 0.613, 5e-4); // the notes' value for kappa = 0.5
    EXPECT_NEAR(half.M_c_eff, eq33_Mc(1.3, 0.5), 1e-14);
    EXPECT_NEAR(half.c_eff * half.M_c_eff, eq33_Me(1.3, 0.5), 1e-14);
    EXPECT_DOUBLE_EQ(half.n_b_eff, 0.65); // Eq. 34
    EXPECT_DOUBLE_EQ(half.A0_eff, 0.4);   // Eq. 35
    // M_c is continuous at kappa -> 1, c jumps from Eq. 33's 0.698 to Table 4's 0.88.
    const auto almost = karlsruhe(1.0 - 1e-9);
    EXPECT_NEAR(almost.M_c_eff, 1.3, 1e-8);
    EXPECT_NEAR(almost.c_eff, 0.698, 5e-4);
}

// The flow direction R' = B n - C (n^2 - I/3) is deviatoric and n:R' = 1 for every Lode angle
// (B and C of Dafalias & Manzari 2004 are built so); with c = 1 it is n itself.
TEST(Sanisand, FlowDirectionIsDeviatoricWithUnitProjection) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (double c : {0.88, 0.7, 1.0}) {
        auto P = karlsruhe();
        P.c = c;
        P.prepare();
        for (int k = 0; k < 20; ++k) {
            const Sym<double> r{u(rng), u(rng), u(rng), u(rng), u(rng), u(rng)};
            const Sym<double> rd = voigt::scale(voigt::deviator(r), 0.5);
            const Sym<double> sigma =
                voigt::scale(voigt::add(rd, voigt::identity<double>()), -100.0);
            Y y = Sanisand::initial_state(sigma, 0.8);
            set_sym_at(y, Sanisand::alpha_index, voigt::scale(rd, 0.9)); // off the axis
            const auto q = sanisand::point(P, {}, y);
            const auto pl = sanisand::plastic(P, q, y);
            EXPECT_NEAR(voigt::trace(pl.Rdev), 0.0, 1e-14);
            EXPECT_NEAR(voigt::ddot(q.n, pl.Rdev), 1.0, 1e-12) << "c = " << c;
            if (c == 1.0) {
                EXPECT_LT(voigt::norm(voigt::sub(pl.Rdev, q.n)), 1e-14);
            }
        }
    }
}

// The loading index L keeps the plastic rate consistent: one Euler increment of the rate
// equations (no drift correction) from a state on the cone leaves f = O(h^2) (ten times smaller
// h: a hundred times smaller f), while the elastic trial leaves f = O(h). Checked for random
// loading directions at a general Lode angle.
TEST(Sanisand, LoadingIndexKeepsThePlasticRateOnTheCone) {
    const auto P = karlsruhe();
    const IntegrationSettings s;
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Y y = Sanisand::initial_state({-100.0, -70.0, -80.0, 10.0, 0.0, -5.0}, 0.8);
    for (int i = 0; i < 10; ++i) {
        step(P, y, Sym<double>{-1e-4, 0.2e-4, 0.5e-4, 0.3e-4, 0.1e-4, 0.0});
    }
    ASSERT_NEAR(sanisand::yield_ratio(P, s, y), 0.0, 1e-15);
    auto f_after = [&](const Sym<double>& de, bool plastic) {
        const Y dy = sanisand::increment(P, s, y, de, plastic);
        Y yn = y;
        for (int i = 0; i < Sanisand::n_state; ++i) {
            yn[i] += dy[i];
        }
        return sanisand::yield_ratio(P, s, yn);
    };
    int loading_cases = 0;
    for (int k = 0; k < 40; ++k) {
        const Sym<double> d{u(rng), u(rng), u(rng), u(rng), u(rng), u(rng)};
        const Sym<double> de = voigt::scale(d, 1e-6 / voigt::norm(d));
        const double f_el = f_after(de, false);
        if (f_el < 1e-5) {
            continue; // unloading or nearly neutral
        }
        ++loading_cases;
        const double f1 = std::fabs(f_after(de, true));
        const double f2 = std::fabs(f_after(voigt::scale(de, 0.1), true));
        EXPECT_LT(f2, 0.02 * f1) << "not second order";
        EXPECT_NEAR(f_after(voigt::scale(de, 0.1), false), 0.1 * f_el, 0.02 * f_el);
    }
    EXPECT_GT(loading_cases, 5);
}

// Pure deviatoric strain from the cone's axis keeps p and e, so G is constant and the exact
// response is ds = 2G de, with G = G0 p_a (2.97 - e)^2/(1 + e) sqrt(p/p_a).
TEST(Sanisand, ElasticShearInsideTheConeIsExactlyHypoelastic) {
    const auto P = karlsruhe();
    const double e = 0.8;
    const Sym<double> s0{-120.0, -70.0, -60.0, 5.0, -3.0, 2.0};
    const Y y0 = Sanisand::initial_state(s0, e);
    const double p = p_of(y0);
    const double G = 70.0 * 100.0 * (2.97 - e) * (2.97 - e) / (1.0 + e) * std::sqrt(p / 100.0);
    // ||dr|| = 2G ||de||/p stays well below the cone radius sqrt(2/3) m = 0.041.
    const Sym<double> de{2.0e-5, -1.5e-5, -0.5e-5, 1.0e-5, 0.5e-5, -0.8e-5};
    Y y = y0;
    const auto st = step(P, y, de);
    EXPECT_EQ(st.status, lane_status::ok);
    EXPECT_EQ(st.rejected, 0.0);
    for (int i = 0; i < 6; ++i) {
        EXPECT_NEAR(y[i] - y0[i], 2.0 * G * de[i], 1e-12 * G * 1e-5) << i;
    }
    EXPECT_EQ(y[6], e);
    EXPECT_LT(sanisand::yield_ratio(P, {}, y), -0.02);
    for (int i = 7; i < Sanisand::n_state; ++i) {
        EXPECT_NEAR(y[i], y0[i], 1e-15) << i; // alpha, z, alpha_in untouched
    }

    // The same on the SIMD path, lane by lane.
    std::array<Y, W> ys;
    std::array<Sym<double>, W> ds;
    for (std::size_t l = 0; l < W; ++l) {
        ys[l] = y0;
        ds[l] = voigt::scale(de, 1.0 - 0.1 * double(l));
    }
    YB yb = pack(ys);
    UpdateStats<Batch> sb;
    material_update<Sanisand, Batch>(P, {}, {}, yb, pack(ds), sb);
    for (std::size_t l = 0; l < W; ++l) {
        const Y yl = lane_of(yb, l);
        for (int i = 0; i < 6; ++i) {
            EXPECT_NEAR(yl[i] - y0[i], 2.0 * G * ds[l][i], 1e-12 * G * 1e-5);
        }
    }
}

// Isotropic compression on the axis never yields (cone without cap). Exact solution:
// e = (1 + e0) exp(-eps_v) - 1 and d sqrt(p) = (K/G) G0 sqrt(p_a) F(e)/2 d eps_v with
// F(e) = (2.97 - e)^2/(1 + e), integrated by Simpson's rule.
TEST(Sanisand, IsotropicCompressionMatchesTheClosedForm) {
    const auto P = karlsruhe();
    const double e0 = 0.8, p0 = 50.0, eps = 0.01;
    IntegrationSettings s;
    s.tolerance = 1e-7;
    Y y = Sanisand::initial_state(isotropic(-p0), e0);
    const auto st = step(P, y, isotropic(-eps / 3.0), s);
    EXPECT_EQ(st.status, lane_status::ok);

    auto F = [&](double t) {
        const double e = (1.0 + e0) * std::exp(-t) - 1.0;
        return (2.97 - e) * (2.97 - e) / (1.0 + e);
    };
    const int n = 2000;
    double integral = F(0.0) + F(eps);
    for (int i = 1; i < n; ++i) {
        integral += (i % 2 ? 4.0 : 2.0) * F(eps * i / n);
    }
    integral *= eps / (3.0 * n);
    const double sqrt_p = std::sqrt(p0) + 0.5 * P.K_over_G * P.G0 * std::sqrt(P.p_a) * integral;
    const double p_exact = sqrt_p * sqrt_p;
    EXPECT_NEAR(p_of(y), p_exact, 2e-6 * p_exact);
    EXPECT_NEAR(y[6], (1.0 + e0) * std::exp(-eps) - 1.0, 1e-9);
    EXPECT_NEAR(y[0], y[1], 1e-9);
    EXPECT_EQ(y[3], 0.0);
    EXPECT_GT(p_of(y), 2.0 * p0); // the test is not trivially satisfied
}

// Plastic loading keeps the stress on the cone, and the result does not depend on how the
// strain path is cut into increments (elastic-plastic crossing inside one increment included).
TEST(Sanisand, ConsistencyAndIncrementSizeIndependence) {
    const auto P = karlsruhe();
    const Sym<double> dir{-1.0, 0.3, 0.7, 0.4, -0.2, 0.1}; // general, with volume change
    const Y y0 = Sanisand::initial_state({-100.0, -60.0, -60.0, 0.0, 0.0, 0.0}, 0.78);
    IntegrationSettings s;
    s.tolerance = 1e-5;

    Y coarse = y0;
    Y fine = y0;
    const int n_coarse = 20, refine = 50;
    const double h = 2.5e-4;
    int plastic_steps = 0;
    for (int i = 0; i < n_coarse; ++i) {
        const auto st = step(P, coarse, voigt::scale(dir, h), s);
        ASSERT_EQ(st.status, lane_status::ok);
        const double f = sanisand::yield_ratio(P, s, coarse);
        EXPECT_LE(f, 1e-12);
        if (i > 0) {
            EXPECT_NEAR(f, 0.0, 1e-12) << "step " << i; // loading: on the cone
            ++plastic_steps;
        }
        for (int k = 0; k < refine; ++k) {
            step(P, fine, voigt::scale(dir, h / refine), s);
        }
    }
    EXPECT_GT(plastic_steps, 10);
    const double sn = voigt::norm(stress_of(fine));
    EXPECT_LT(voigt::norm(voigt::sub(stress_of(coarse), stress_of(fine))), 2e-4 * sn);
    EXPECT_NEAR(coarse[6], fine[6], 1e-8);
    EXPECT_LT(voigt::norm(voigt::sub(sym_at(coarse, 7), sym_at(fine, 7))), 2e-4);
    // The path went far from the start (not a trivial comparison).
    EXPECT_GT(voigt::norm(voigt::sub(stress_of(fine), stress_of(y0))), 0.3 * sn);
}

// Undrained (isochoric) triaxial compression at large strain reaches the critical state:
// eta -> M_c and e_c(p) -> e, i.e. p -> p_cs(e), for a dense and a loose sample.
TEST(Sanisand, UndrainedCompressionReachesTheCriticalState) {
    const auto P = karlsruhe();
    for (double e : {0.78, 0.90}) {
        Y y = Sanisand::initial_state(isotropic(-100.0), e);
        for (int i = 0; i < 500; ++i) {
            ASSERT_EQ(step(P, y, isochoric(1e-3)).status, lane_status::ok);
        }
        const double p = p_of(y);
        EXPECT_NEAR(q_of(y) / p / P.M_c, 1.0, 1e-4) << "e = " << e;
        EXPECT_NEAR(psi_of(P, y), 0.0, 1e-4) << "e = " << e;
        EXPECT_NEAR(p, p_critical(P, e), 1e-3 * p) << "e = " << e;
        EXPECT_EQ(y[6], e);
    }
}

// Drained triaxial compression at constant lateral stress 100 kPa: eta -> M_c, psi -> 0 and
// p -> 3 sigma_3/(3 - M_c); the dense sample dilates to the critical void ratio, the loose one
// contracts to it (psi halves about every 20 % of axial strain, hence the long path).
TEST(Sanisand, DrainedCompressionReachesTheCriticalState) {
    const auto P = karlsruhe();
    const double sigma3 = 100.0;
    const double p_cs = 3.0 * sigma3 / (3.0 - P.M_c);
    for (double e : {0.72, 0.92}) {
        Y y = Sanisand::initial_state(isotropic(-sigma3), e);
        for (int i = 0; i < 1000; ++i) {
            ASSERT_EQ(drained_step(P, y, 2e-3, sigma3).status, lane_status::ok);
        }
        EXPECT_NEAR(q_of(y) / p_of(y) / P.M_c, 1.0, 3e-4) << "e = " << e;
        EXPECT_NEAR(p_of(y), p_cs, 3e-4 * p_cs);
        EXPECT_NEAR(psi_of(P, y), 0.0, 2e-4) << "e = " << e;
        EXPECT_NEAR(y[6], e_crit(P, p_cs), 2e-4);
        EXPECT_GT(std::fabs(y[6] - e), 0.07); // dilated / contracted
    }
}

// Undrained triaxial extension: |eta| -> c M_c (Lode interpolation g = c in extension).
TEST(Sanisand, UndrainedExtensionReachesTheExtensionRatio) {
    for (double kappa : {1.0, 0.5}) {
        const auto P = karlsruhe(kappa);
        const double Me = kappa < 1.0 ? eq33_Me(P.M_c, kappa) : P.c * P.M_c;
        Y y = Sanisand::initial_state(isotropic(-100.0), 0.8);
        for (int i = 0; i < 1000; ++i) {
            ASSERT_EQ(step(P, y, isochoric(-1e-3)).status, lane_status::ok);
        }
        EXPECT_NEAR(-q_of(y) / p_of(y) / Me, 1.0, 2e-3) << "kappa = " << kappa;
        EXPECT_NEAR(psi_of(P, y), 0.0, 2e-3);
    }
}

// Eq. 33: kappa < 1 lowers the critical stress ratio in compression to 6 sin(k phi)/(3 - sin).
TEST(Sanisand, RoughnessLowersTheCriticalStressRatio) {
    for (double kappa : {0.8, 0.5}) {
        const auto P = karlsruhe(kappa);
        const double Mk = eq33_Mc(1.3, kappa);
        Y y = Sanisand::initial_state(isotropic(-100.0), 0.8);
        for (int i = 0; i < 1000; ++i) {
            ASSERT_EQ(step(P, y, isochoric(1e-3)).status, lane_status::ok);
        }
        EXPECT_NEAR(q_of(y) / p_of(y), Mk, 1e-3 * Mk) << "kappa = " << kappa;
        EXPECT_LT(Mk, 1.3 - 0.1);
        EXPECT_NEAR(psi_of(P, y), 0.0, 1e-3);
    }
}

// The fabric tensor z grows only under dilation: zero throughout a contractive drained path,
// zero in the contractive part of a dense undrained path (p falling) and growing after the
// phase transformation (p rising), towards -z_max n (z:n < 0).
TEST(Sanisand, FabricGrowsOnlyAfterPhaseTransformation) {
    const auto P = karlsruhe();
    {
        Y y = Sanisand::initial_state(isotropic(-100.0), 0.95);
        double e_prev = y[6];
        for (int i = 0; i < 150; ++i) {
            drained_step(P, y, 2e-3, 100.0);
            EXPECT_LE(y[6], e_prev + 1e-12); // contractive all the way
            e_prev = y[6];
            for (int k = 0; k < 6; ++k) {
                ASSERT_EQ(y[Sanisand::z_index + k], 0.0) << "step " << i;
            }
        }
        EXPECT_LT(y[6], 0.95 - 0.02);
    }
    {
        // The step whose end has the lowest p contains the phase transformation.
        Y y = Sanisand::initial_state(isotropic(-100.0), 0.80);
        std::vector<double> p, zn;
        for (int i = 0; i < 100; ++i) {
            step(P, y, isochoric(2e-4));
            p.push_back(p_of(y));
            zn.push_back(voigt::norm(sym_at(y, Sanisand::z_index)));
        }
        const auto i_pt = std::min_element(p.begin(), p.end()) - p.begin();
        ASSERT_GT(i_pt, 5);
        ASSERT_LT(i_pt, 90);
        for (long i = 0; i < i_pt; ++i) {
            EXPECT_EQ(zn[i], 0.0) << "step " << i;
        }
        for (long i = i_pt + 1; i < 100; ++i) {
            EXPECT_GT(zn[i], zn[i - 1]) << "step " << i;
        }
        const auto q = sanisand::point(P, {}, y);
        EXPECT_LT(voigt::ddot(sym_at(y, Sanisand::z_index), q.n), -1.0);
    }
}

// A loose sample under cyclic isochoric (undrained) strain-controlled loading liquefies: the
// mean pressure at the end of each cycle falls cycle by cycle to a small fraction of p0, on the
// scalar and the SIMD path alike (the same to round-off until the pressure floor is reached,
// where lanes part ways through step selection), without NaN; afterwards the state stays
// defined at low p.
TEST(Sanisand, LooseSampleLiquefiesInCyclicUndrainedLoading) {
    const auto P = karlsruhe();
    const IntegrationSettings s;
    const double p0 = 100.0, amp = 2e-3;
    const int per_quarter = 50, cycles = 10;
    std::array<Y, W> ys;
    for (std::size_t l = 0; l < W; ++l) {
        ys[l] = Sanisand::initial_state(isotropic(-p0), 0.87);
    }
    Y y = ys[0];
    YB yb = pack(ys);
    std::vector<double> p_end;
    int unreliable = 0;
    for (int c = 0; c < cycles; ++c) {
        for (int i = 0; i < 4 * per_quarter; ++i) {
            const double sign = (i < per_quarter || i >= 3 * per_quarter) ? 1.0 : -1.0;
            const Sym<double> de = isochoric(sign * amp / per_quarter);
            const auto st = step(P, y, de, s);
            ASSERT_GE(st.status, lane_status::unreliable);
            ASSERT_TRUE(all_finite(y));
            ASSERT_GE(p_of(y), s.min_pressure * (1.0 - 1e-12));
            unreliable += st.status < 0.5;
            std::array<Sym<double>, W> ds;
            ds.fill(de);
            UpdateStats<Batch> sb;
            material_update<Sanisand, Batch>(P, s, {}, yb, pack(ds), sb);
        }
        p_end.push_back(p_of(y));
        for (std::size_t l = 0; l < W; ++l) {
            const Y yl = lane_of(yb, l);
            ASSERT_TRUE(all_finite(yl));
            if (p_end.back() > 5.0) {
                EXPECT_NEAR(p_of(yl), p_end.back(), 1e-8 * p0) << "cycle " << c + 1;
            }
        }
    }
    for (int c = 1; c < 5; ++c) {
        EXPECT_LT(p_end[c], 0.8 * p_end[c - 1]) << "cycle " << c + 1;
    }
    EXPECT_LT(p_end[4], 0.1 * p0);
    EXPECT_LT(*std::min_element(p_end.begin(), p_end.end()), 0.01 * p0);
    EXPECT_GT(unreliable, 0); // the pressure floor was reached
}

// Hard inputs end in a defined state without NaN: zero and tensile start stress (pressure
// floor, unreliable), a huge increment (accurate), a huge extension (cut-off at the floor),
// and non-finite input (failed, state returned unchanged).
TEST(Sanisand, HardCasesEndInDefinedStates) {
    const auto P = karlsruhe();
    const IntegrationSettings s;
    {
        Y y = Sanisand::initial_state(isotropic(0.0), 0.8);
        const auto st = step(P, y, isotropic(-1e-3));
        EXPECT_EQ(st.status, lane_status::unreliable);
        EXPECT_TRUE(all_finite(y));
        EXPECT_GT(p_of(y), 0.1); // compressed from the floor
        EXPECT_LE(sanisand::yield_ratio(P, s, y), 1e-12);
    }
    {
        Y y = Sanisand::initial_state({30.0, 10.0, 20.0, 5.0, 0.0, 0.0}, 0.8);
        set_sym_at(y, Sanisand::alpha_index, Sym<double>{0.6, -0.3, -0.3, 0.2, 0.0, 0.0});
        const auto st = step(P, y, isochoric(1e-3));
        EXPECT_EQ(st.status, lane_status::unreliable);
        EXPECT_TRUE(all_finite(y));
        EXPECT_GE(p_of(y), s.min_pressure * (1.0 - 1e-12));
        EXPECT_LE(sanisand::yield_ratio(P, s, y), 1e-12);
    }
    {
        const Y y0 = Sanisand::initial_state({-100.0, -50.0, -50.0, 0.0, 0.0, 0.0}, 0.8);
        const Sym<double> big{-1e-2, 0.3e-2, 0.2e-2, 0.5e-2, 0.0, 0.0};
        Y one = y0;
        const auto st = step(P, one, big);
        EXPECT_EQ(st.status, lane_status::ok);
        EXPECT_GT(st.substeps, 5.0);
        EXPECT_GE(st.rate_evaluations, 2.0 * (st.substeps + st.rejected));
        Y many = y0;
        for (int i = 0; i < 200; ++i) {
            step(P, many, voigt::scale(big, 1.0 / 200.0));
        }
        EXPECT_LT(voigt::norm(voigt::sub(stress_of(one), stress_of(many))),
                  1e-2 * voigt::norm(stress_of(many)));
        EXPECT_NEAR(sanisand::yield_ratio(P, s, one), 0.0, 1e-12);
    }
    {
        Y y = Sanisand::initial_state({-100.0, -50.0, -50.0, 0.0, 0.0, 0.0}, 0.8);
        const auto st = step(P, y, isotropic(3e-2 / 3.0)); // pulls the sample apart
        EXPECT_EQ(st.status, lane_status::unreliable);
        EXPECT_TRUE(all_finite(y));
        EXPECT_NEAR(p_of(y), s.min_pressure, 1e-12);
        EXPECT_NEAR(y[6], 1.8 * std::exp(3e-2) - 1.0, 1e-3); // e follows the strain
        EXPECT_LE(sanisand::yield_ratio(P, s, y), 1e-12);
    }
    {
        const double nan = std::numeric_limits<double>::quiet_NaN();
        const Y y0 = Sanisand::initial_state(isotropic(-100.0), 0.8);
        Y y = y0;
        y[Sanisand::z_index + 1] = nan;
        const Y bad = y;
        EXPECT_EQ(step(P, y, isochoric(1e-3)).status, lane_status::failed);
        EXPECT_EQ(std::memcmp(&y, &bad, sizeof(Y)), 0);
        y = y0;
        EXPECT_EQ(step(P, y, {nan, 0.0, 0.0, 0.0, 0.0, 0.0}).status, lane_status::failed);
        EXPECT_EQ(y, y0);
        // SIMD: a NaN lane fails alone, the others integrate as on the scalar path.
        std::array<Y, W> ys;
        std::array<Sym<double>, W> ds;
        for (std::size_t l = 0; l < W; ++l) {
            ys[l] = y0;
            ds[l] = isochoric(1e-3 * double(l + 1));
        }
        ds[0][2] = nan;
        YB yb = pack(ys);
        UpdateStats<Batch> sb;
        material_update<Sanisand, Batch>(P, s, {}, yb, pack(ds), sb);
        EXPECT_EQ(simd::lane(sb.status, 0), lane_status::failed);
        EXPECT_EQ(lane_of(yb, 0), y0);
        for (std::size_t l = 1; l < W; ++l) {
            Y ref = y0;
            step(P, ref, ds[l]);
            const Y yl = lane_of(yb, l);
            for (int k = 0; k < Sanisand::n_state; ++k) {
                EXPECT_NEAR(yl[k], ref[k], 1e-10 * (1.0 + std::fabs(ref[k])));
            }
        }
    }
}

// The rate stiffness equals the derivative of one tiny integrated step (one fixed substep) in
// the loading branch and in the elastic unloading branch, per column (shear columns perturb the
// tensor component, i.e. eps_ij and eps_ji together).
TEST(Sanisand, RateStiffnessMatchesFiniteDifferenceOfATinyStep) {
    const auto P = karlsruhe();
    const IntegrationSettings s;
    Y y = Sanisand::initial_state({-100.0, -70.0, -80.0, 5.0, 0.0, -3.0}, 0.8);
    for (int i = 0; i < 10; ++i) {
        step(P, y, Sym<double>{-1e-4, 0.2e-4, 0.3e-4, 0.2e-4, 0.1e-4, 0.0});
    }
    ASSERT_NEAR(sanisand::yield_ratio(P, s, y), 0.0, 1e-12);
    SubstepControl<double> one;
    one.fixed_substeps = 1.0;
    const double h = 1e-8, delta = 1e-10;
    for (double sense : {1.0, -1.0}) {
        const Sym<double> dir = voigt::scale(Sym<double>{-1.0, 0.2, 0.3, 0.2, 0.1, 0.0}, sense);
        const Sym<double> base = voigt::scale(dir, h);
        const auto K = Sanisand::rate_stiffness(P, s, y, dir);
        double kmax = 0.0;
        for (const auto& col : K) {
            kmax = std::max(kmax, voigt::norm(col));
        }
        for (int j = 0; j < 6; ++j) {
            Sym<double> dp = base, dm = base;
            dp[j] += delta;
            dm[j] -= delta;
            Y yp = y, ym = y;
            step(P, yp, dp, s, one);
            step(P, ym, dm, s, one);
            for (int i = 0; i < 6; ++i) {
                const double fd = (yp[i] - ym[i]) / (2.0 * delta);
                EXPECT_NEAR(K[j][i], fd, 1e-4 * kmax)
                    << "sense " << sense << " col " << j << " row " << i;
            }
        }
        // Loading is softer than elastic unloading.
        if (sense > 0.0) {
            const auto Ke = Sanisand::rate_stiffness(P, s, y, voigt::scale(dir, -1.0));
            EXPECT_LT(K[0][0], 0.9 * Ke[0][0]);
        }
    }
}

// Fixed substeps (the engine's perturbed evaluations) across the elastic-plastic transition:
// no error control, one extra substep for the crossing, second-order convergence to the
// adaptive result, and the state ends on the cone.
TEST(Sanisand, FixedSubstepsConvergeAcrossTheTransition) {
    const auto P = karlsruhe();
    const Y y0 = Sanisand::initial_state(isotropic(-100.0), 0.8);
    const Sym<double> de = voigt::scale(Sym<double>{-1.0, 0.4, 0.4, 0.3, 0.0, 0.0}, 1e-3);
    IntegrationSettings tight;
    tight.tolerance = 1e-8;
    Y ref = y0;
    ASSERT_EQ(step(P, ref, de, tight).status, lane_status::ok);
    double previous_error = 1e30;
    for (double n : {4.0, 8.0, 16.0, 32.0}) {
        SubstepControl<double> fixed;
        fixed.fixed_substeps = n;
        Y y = y0;
        const auto st = step(P, y, de, {}, fixed);
        EXPECT_EQ(st.status, lane_status::ok);
        EXPECT_EQ(st.rejected, 0.0);
        EXPECT_GE(st.substeps, n);
        EXPECT_LE(st.substeps, n + 1.0);
        EXPECT_NEAR(sanisand::yield_ratio(P, {}, y), 0.0, 1e-12);
        const double error = voigt::norm(voigt::sub(stress_of(y), stress_of(ref)));
        EXPECT_LT(error, 0.45 * previous_error) << "n = " << n; // ~1/4 for second order
        previous_error = error;
    }
    EXPECT_LT(previous_error, 1e-3 * voigt::norm(stress_of(ref)));
}

// The SIMD path reproduces the scalar path lane by lane on different paths, with lanes that
// load, unload (reversals every 30 steps) and cross the cone in the same batch. (Lanes at the
// pressure floor are compared in the liquefaction test up to the floor only: there the
// response is so sensitive that round-off differences of the SIMD math functions grow.)
TEST(Sanisand, SimdPathMatchesScalarPath) {
    const auto P = karlsruhe();
    const std::array<Sym<double>, 4> dirs{
        Sym<double>{-1.0, 0.5, 0.5, 0.0, 0.0, 0.0}, Sym<double>{0.2, -0.6, 0.3, 0.8, -0.3, 0.2},
        Sym<double>{-0.2, 0.4, -0.5, 0.0, 0.3, 0.0}, Sym<double>{-0.5, 0.1, 0.6, 0.0, 0.4, 0.0}};
    std::array<Y, W> ys;
    std::array<Y, W> ref;
    for (std::size_t l = 0; l < W; ++l) {
        ys[l] = Sanisand::initial_state({-80.0 - 5.0 * l, -50.0, -60.0, 3.0, 0.0, 0.0},
                                        0.70 + 0.01 * l);
        ref[l] = ys[l];
    }
    YB yb = pack(ys);
    double p_low = 1e30, substeps = 0.0;
    for (int i = 0; i < 120; ++i) {
        std::array<Sym<double>, W> ds;
        for (std::size_t l = 0; l < W; ++l) {
            const double sense = (i / 30) % 2 ? -1.0 : 1.0;
            ds[l] = voigt::scale(dirs[l % 4], sense * 1e-4);
            const auto st = step(P, ref[l], ds[l]);
            ASSERT_EQ(st.status, lane_status::ok) << "lane " << l << " step " << i;
            p_low = std::min(p_low, p_of(ref[l]));
            substeps += st.substeps;
        }
        UpdateStats<Batch> sb;
        material_update<Sanisand, Batch>(P, {}, {}, yb, pack(ds), sb);
    }
    EXPECT_GT(p_low, 2.0 * IntegrationSettings{}.min_pressure); // the floor never acted
    EXPECT_GT(substeps, 2.0 * 120 * W);                         // the lanes did substep
    for (std::size_t l = 0; l < W; ++l) {
        const Y yl = lane_of(yb, l);
        for (int k = 0; k < Sanisand::n_state; ++k) {
            EXPECT_NEAR(yl[k], ref[l][k], 1e-9 * (1.0 + std::fabs(ref[l][k])))
                << "lane " << l << " entry " << k;
        }
    }
}
