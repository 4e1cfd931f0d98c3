// Algorithm 1's switch from the rate to the perturbation Newton Jacobian inside a sub-increment
// (InterfaceSettings::newton_switch_ratio). The case is a real one: a rough Sanisand band of the
// coarse §6 run's first wall step (docs/large-scale-test.md, session 18), held at 212 equal
// sub-increments, whose shear reverses (tau -4.4 -> +1.5 kPa) while t_N falls from -2.65 to
// -1.80 kPa. Near its cone the rate stiffness at the start state is up to 20x the elastic one;
// the rate Newton creeps, and each failure halves the held size for the rest of the call. In
// session 18 the call ended at the work limit after 4.8e5 sub-increments; most of that was a
// polishing correction taken far from the solution (fixed in session 19, kernels/
// interface_newton.hpp). Without the switch it now succeeds with 1.3e4 sub-increments, with it
// 16x fewer. Checked: with the switch the call takes far fewer sub-increments and agrees with
// fine fixed sub-increments; lanes whose rate Newton contracts are untouched bit for bit; a SIMD
// lane ends where the scalar one does and spares its neighbours.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>

#include "tests/engine/interface_fixtures.hpp"

using namespace ifsim;
using namespace ifsim::test;

namespace {

constexpr int NS = Sanisand::n_state;
constexpr std::size_t W = simd::lanes;

// Rough point 28 at (1.2, 0.1009, 0.8526), increment 10 of the run with the work bound.
InterfaceState<double, NS> reversing_band() {
    const std::array<double, NS> y{-2.6530458944974695,
                                   -5.69609985046629,
                                   -4.266734801184905,
                                   -4.432083334931396,
                                   -0.024630076105260898,
                                   0.0,
                                   0.6625037847728729,
                                   -0.359447820968823,
                                   0.3454627354988037,
                                   0.013985085470019299,
                                   1.026626490423189,
                                   0.005699636014313084,
                                   0.0001946891498460789,
                                   14.087714552376159,
                                   -13.450702494153333,
                                   -0.6370120582228248,
                                   -40.12460481523524,
                                   -0.22326225151911297,
                                   -0.008072225764304709,
                                   -0.2500000000000653,
                                   0.5000000000000104,
                                   -0.24999999999994518,
                                   -1.6767610274445542e-12,
                                   3.1847322269981044e-14,
                                   0.0};
    InterfaceState<double, NS> st;
    for (int k = 0; k < NS; ++k) {
        st.y[k] = y[k];
    }
    st.eps_n = 0.0081289555500598468;
    st.eps_p1 = 0.00026965923252022822;
    st.eps_p2 = 0.0015780530629871076;
    st.gamma1 = -0.02284845642357923;
    st.gamma2 = 6.9181464616450924e-06;
    return st;
}

InterfaceInput<double> held_call(double subincrements) {
    return {-1.799185104182361,  0.00078897698920902734, -1.5972851122310616e-05,
            -3.8629562530974222, -3.8629562530974222,    subincrements};
}

InterfaceSettings the_run_settings(double switch_ratio) {
    InterfaceSettings s; // the scene's rough pair: novel 3D, adaptive, d_s = 6 mm, rate Jacobian
    s.adaptive = true;
    s.shear_band_thickness = 0.006;
    s.newton_switch_ratio = switch_ratio;
    s.work_model_substeps = 0.0; // the switch on its own
    s.work_newton_iterations = 0.0;
    return s;
}

bool same_bits(double a, double b) {
    return std::memcmp(&a, &b, sizeof a) == 0;
}

} // namespace

TEST(InterfaceNewtonSwitch, HeldReversingBandHalvesLessAndAgreesWithFineSubincrements) {
    const auto mp = karlsruhe_sanisand(1.0);
    const auto in = held_call(212.0);
    const auto creeping = direct_update<Sanisand>(mp, the_run_settings(0.0), reversing_band(), in);
    // Without the switch: the creeping Newton halves the held size many times (measured 13 422
    // sub-increments for the 212 held ones).
    ASSERT_EQ(creeping.stats.status, lane_status::ok);
    EXPECT_GT(creeping.stats.subincrements, 5.0e3);

    const InterfaceSettings s = the_run_settings(0.5);
    const auto r = direct_update<Sanisand>(mp, s, reversing_band(), in);
    ASSERT_EQ(r.stats.status, lane_status::ok);
    EXPECT_LT(r.stats.subincrements, 0.2 * creeping.stats.subincrements); // measured 839
    EXPECT_LT(r.stats.model_substeps, 0.1 * s.max_model_substeps);

    InterfaceSettings fine = the_run_settings(0.5);
    fine.adaptive = false;
    fine.max_subincrement = 1.0e-6;
    const auto ref = direct_update<Sanisand>(mp, fine, reversing_band(), held_call(0.0));
    ASSERT_EQ(ref.stats.status, lane_status::ok);
    // The reversed shear (tau about +1.5 kPa) to the adaptive tolerance of the stress.
    const double scale = std::abs(in.t_N);
    for (int k = 0; k < 5; ++k) {
        EXPECT_LT(std::abs(r.st.y[k] - ref.st.y[k]), 5.0 * s.adaptive_tolerance * scale)
            << "stress " << k << ": " << r.st.y[k] << " against " << ref.st.y[k];
    }
    EXPECT_GT(r.st.y[3], 0.5); // the shear did reverse
}

// A lane whose rate Newton contracts by more than the ratio in every iteration never switches:
// the same bits and the same number of evaluations with the switch on and off.
TEST(InterfaceNewtonSwitch, ContractingCallsAreUntouched) {
    const auto mp = karlsruhe_sanisand(1.0);
    for (const double v : {0.0, 3.0, 7.0}) {
        const auto in = ordinary_sanisand_call(v);
        const auto off =
            direct_update<Sanisand>(mp, the_run_settings(0.0), ordinary_sanisand_band(), in);
        const auto on =
            direct_update<Sanisand>(mp, the_run_settings(0.5), ordinary_sanisand_band(), in);
        ASSERT_EQ(off.stats.status, lane_status::ok) << v;
        EXPECT_EQ(on.stats.evaluations, off.stats.evaluations) << v;
        for (int k = 0; k < NS; ++k) {
            EXPECT_TRUE(same_bits(on.st.y[k], off.st.y[k])) << v << " entry " << k;
        }
        EXPECT_TRUE(same_bits(on.st.eps_n, off.st.eps_n)) << v;
    }
}

// The switching lane in a batch of ordinary ones: it ends where the scalar path ends, and its
// neighbours give the bits they give with the switch off (the switch is a per-lane mask).
TEST(InterfaceNewtonSwitch, BatchLaneMatchesScalarAndSparesItsNeighbours) {
    if (W < 2) {
        GTEST_SKIP() << "scalar build";
    }
    const auto mp = karlsruhe_sanisand(1.0);
    const std::size_t hard = 0;
    auto lane_state = [&](std::size_t l) {
        return l == hard ? reversing_band() : ordinary_sanisand_band();
    };
    auto lane_input = [&](std::size_t l) {
        return l == hard ? held_call(212.0) : ordinary_sanisand_call(static_cast<double>(l));
    };
    auto run = [&](const InterfaceSettings& s) {
        auto r = batched_update<Sanisand>(mp, s, lane_state, lane_input);
        return std::pair{r.st, r.stats};
    };
    const auto [with, with_stats] = run(the_run_settings(0.5));
    const auto [without, without_stats] = run(the_run_settings(0.0));
    const auto scalar =
        direct_update<Sanisand>(mp, the_run_settings(0.5), reversing_band(), held_call(212.0));
    ASSERT_EQ(simd::lane(with_stats.status, hard), lane_status::ok);
    // xsimd's pow/exp/log round differently from libm, and along this reversal the rounding
    // moves where a held sub-increment's Newton fails (measured: 3 356 sub-increments in the
    // batch, 1 680 on the scalar path). Both end at the same solution to well within the
    // adaptive tolerance (measured: 2.3e-4 kPa apart).
    for (int k = 0; k < 5; ++k) {
        EXPECT_NEAR(simd::lane(with.y[k], hard), scalar.st.y[k],
                    0.25 * the_run_settings(0.5).adaptive_tolerance * std::abs(held_call(0.0).t_N))
            << "stress " << k;
    }
    for (std::size_t l = 0; l < W; ++l) {
        if (l == hard) {
            continue;
        }
        EXPECT_EQ(simd::lane(with_stats.status, l), lane_status::ok) << "lane " << l;
        for (int k = 0; k < NS; ++k) {
            EXPECT_TRUE(same_bits(simd::lane(with.y[k], l), simd::lane(without.y[k], l)))
                << "lane " << l << " entry " << k;
        }
    }
}

// The other target of the switch (newton_switch_broyden = false): the perturbation Jacobian,
// k + 1 more evaluations per iteration. The held reversing band ends with it, at the
// solution the Broyden updates reach (both meet Eqs. 18-20 to the tolerance on the same
// discretisation up to where a held sub-increment halves).
TEST(InterfaceNewtonSwitch, PerturbationTargetEndsTheHeldBandToo) {
    const auto mp = karlsruhe_sanisand(1.0);
    const auto in = held_call(212.0);
    InterfaceSettings perturbation = the_run_settings(0.5);
    perturbation.newton_switch_broyden = false;
    const auto p = direct_update<Sanisand>(mp, perturbation, reversing_band(), in);
    // (It halves as often as the rate Newton alone, 1.3e4 sub-increments: the k + 1
    // evaluations per iteration buy nothing on this band since the polish guard.)
    ASSERT_EQ(p.stats.status, lane_status::ok);
    const auto b = direct_update<Sanisand>(mp, the_run_settings(0.5), reversing_band(), in);
    ASSERT_EQ(b.stats.status, lane_status::ok);
    // The perturbation lanes cost evaluations the Broyden updates do not.
    EXPECT_GT(p.stats.evaluations / p.stats.newton_iterations,
              b.stats.evaluations / b.stats.newton_iterations);
    for (int k = 0; k < 5; ++k) {
        EXPECT_LT(std::abs(p.st.y[k] - b.st.y[k]),
                  5.0 * perturbation.adaptive_tolerance * std::abs(in.t_N))
            << "stress " << k << ": " << p.st.y[k] << " against " << b.st.y[k];
    }
}
