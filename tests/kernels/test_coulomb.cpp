// Coulomb penalty friction: exact stick and slip, open contact, and consistent derivatives
// against central finite differences, on the scalar and the SIMD path.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "kernels/coulomb.hpp"

using namespace ifsim;

namespace {

CoulombParams params() {
    CoulombParams p;
    p.friction_coefficient = 0.25;
    p.tangential_stiffness = 6.0e3;
    return p;
}

} // namespace

TEST(Coulomb, StickIsLinearPenalty) {
    const auto p = params();
    // |tau_tr| = 6000 * 1e-3 = 6 kPa < 0.25 * 100 kPa.
    const auto r = coulomb_update<double>(p, -100.0, 0.0, 0.0, 1.0e-3, 0.0);
    EXPECT_FALSE(r.slipping);
    EXPECT_DOUBLE_EQ(r.tau1, 6.0);
    EXPECT_DOUBLE_EQ(r.tau2, 0.0);
    EXPECT_DOUBLE_EQ(r.dtau_ddg[0][0], 6.0e3);
    EXPECT_DOUBLE_EQ(r.dtau_ddg[0][1], 0.0);
}

TEST(Coulomb, SlipLandsExactlyOnTheConeAlongTheTrialDirection) {
    const auto p = params();
    const auto r = coulomb_update<double>(p, -100.0, 10.0, 0.0, 0.01, 0.02);
    EXPECT_TRUE(r.slipping);
    EXPECT_NEAR(std::hypot(r.tau1, r.tau2), 25.0, 1e-12);
    const double tr1 = 10.0 + 60.0, tr2 = 120.0;
    EXPECT_NEAR(r.tau1 * tr2 - r.tau2 * tr1, 0.0, 1e-9); // parallel to the trial traction
    EXPECT_GT(r.tau1 * tr1 + r.tau2 * tr2, 0.0);
}

TEST(Coulomb, ReversalFromSlipSticksFirst) {
    const auto p = params();
    // On the cone at +25 kPa, a small reversal unloads elastically.
    const auto r = coulomb_update<double>(p, -100.0, 25.0, 0.0, -1.0e-3, 0.0);
    EXPECT_FALSE(r.slipping);
    EXPECT_DOUBLE_EQ(r.tau1, 19.0);
}

TEST(Coulomb, OpenContactCarriesNoShear) {
    const auto p = params();
    const auto r = coulomb_update<double>(p, 0.0, 5.0, 1.0, 1.0e-3, 0.0);
    EXPECT_TRUE(r.open);
    EXPECT_EQ(r.tau1, 0.0);
    EXPECT_EQ(r.tau2, 0.0);
    EXPECT_EQ(r.dtau_ddg[0][0], 0.0);
    const auto t = coulomb_update<double>(p, 15.0, 5.0, 1.0, 1.0e-3, 0.0);
    EXPECT_TRUE(t.open);
    EXPECT_EQ(t.tau1, 0.0);
}

TEST(Coulomb, DerivativesMatchCentralDifferencesInSlipAndStick) {
    const auto p = params();
    const std::array<std::array<double, 5>, 3> cases = {{
        {-100.0, 3.0, -2.0, 4.0e-3, 2.5e-3},   // slip
        {-100.0, 3.0, -2.0, 1.0e-4, -2.0e-4},  // stick
        {-250.0, -40.0, 10.0, -6.0e-3, 1.0e-3} // slip, other quadrant
    }};
    for (const auto& c : cases) {
        const auto r = coulomb_update<double>(p, c[0], c[1], c[2], c[3], c[4]);
        const double h = 1.0e-7;
        for (int b = 0; b < 2; ++b) {
            std::array<double, 2> dgp = {c[3], c[4]}, dgm = {c[3], c[4]};
            dgp[b] += h;
            dgm[b] -= h;
            const auto rp = coulomb_update<double>(p, c[0], c[1], c[2], dgp[0], dgp[1]);
            const auto rm = coulomb_update<double>(p, c[0], c[1], c[2], dgm[0], dgm[1]);
            EXPECT_NEAR(r.dtau_ddg[0][b], (rp.tau1 - rm.tau1) / (2 * h), 1e-4 * 6e3);
            EXPECT_NEAR(r.dtau_ddg[1][b], (rp.tau2 - rm.tau2) / (2 * h), 1e-4 * 6e3);
        }
        const double hn = 1.0e-5;
        const auto rp = coulomb_update<double>(p, c[0] + hn, c[1], c[2], c[3], c[4]);
        const auto rm = coulomb_update<double>(p, c[0] - hn, c[1], c[2], c[3], c[4]);
        EXPECT_NEAR(r.dtau_dtN[0], (rp.tau1 - rm.tau1) / (2 * hn), 1e-7);
        EXPECT_NEAR(r.dtau_dtN[1], (rp.tau2 - rm.tau2) / (2 * hn), 1e-7);
    }
}

TEST(Coulomb, SimdLanesEqualScalar) {
    const auto p = params();
    constexpr std::size_t W = simd::lanes;
    alignas(64) double tn[W], t1[W], t2[W], g1[W], g2[W];
    for (std::size_t i = 0; i < W; ++i) {
        tn[i] = i % 3 == 0 ? 5.0 : -50.0 - 20.0 * i;
        t1[i] = 2.0 * i - 5.0;
        t2[i] = 1.0 - 0.5 * i;
        g1[i] = (i % 2 ? 1.0 : -1.0) * 1e-3 * i;
        g2[i] = 2e-4 * i;
    }
    const auto rb =
        coulomb_update<simd::batch>(p, simd::batch::load_aligned(tn), simd::batch::load_aligned(t1),
                                    simd::batch::load_aligned(t2), simd::batch::load_aligned(g1),
                                    simd::batch::load_aligned(g2));
    for (std::size_t i = 0; i < W; ++i) {
        const auto rs = coulomb_update<double>(p, tn[i], t1[i], t2[i], g1[i], g2[i]);
        EXPECT_NEAR(simd::lane(rb.tau1, i), rs.tau1, 1e-12 * (1 + std::abs(rs.tau1)));
        EXPECT_NEAR(simd::lane(rb.tau2, i), rs.tau2, 1e-12 * (1 + std::abs(rs.tau2)));
        EXPECT_NEAR(simd::lane(rb.dtau_ddg[0][1], i), rs.dtau_ddg[0][1], 1e-9);
    }
}
