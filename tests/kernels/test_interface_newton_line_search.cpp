// Backtracking on Algorithm 1's Newton (InterfaceSettings::newton_line_search). The case is a
// real one: rough point 170 of the fine §6 Sanisand run with the rate Jacobian throughout
// (docs/large-scale-test.md, session 29), which stopped that run at 0.83 mm of wall travel. Its
// band sits on Sanisand's yield cone with in-plane targets relaxed to t_N: a normal-strain step
// one way unloads elastically (stiff), the other way flows plastically (soft). The full Newton
// steps jump across that kink in a two-cycle (residual 0.0022 <-> 0.0123) whichever Jacobian
// they use, so the halving of the sub-increment and the second try on the perturbation Jacobian
// cannot end it. Checked: without backtracking the call fails, with it the call ends at the
// solution fine fixed sub-increments reach; calls whose Newton lowers the residual in every
// step are untouched bit for bit; a SIMD lane ends where the scalar one does.
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

// The committed state of point 170 at (1.2, 0.139, 0.903) m, from the run's replay.toml.
InterfaceState<double, NS> band_on_its_cone() {
    const std::array<double, NS> y{
        -3.8494231847991234,    -5.31542515721746,    -3.292285520762162,
        1.888949900940166,      -0.04077073184063914, 0.0,
        0.6321401715380167,     -0.0769690832091492,  0.2857340401070621,
        -0.20876495689791288,   -0.42649041937758014, 0.009121260161945529,
        -8.929609028632585e-06, 17.03022080052527,    -8.339927343419852,
        -8.690293457105417,     -39.75885764828305,   -0.4167039263128679,
        -0.010793255254511804,  -0.42132543952053547, 0.21168626354289324,
        0.20963917597764226,    0.990378231331919,    0.010129661805703526,
        0.0002556306896334231};
    InterfaceState<double, NS> st;
    for (int k = 0; k < NS; ++k) {
        st.y[k] = y[k];
    }
    st.eps_n = 0.0029229191634930463;
    st.eps_p1 = -0.005225705251156426;
    st.eps_p2 = -0.0061531739109786975;
    st.gamma1 = -0.02305456631294562;
    st.gamma2 = -7.232326860583846e-05;
    return st;
}

// The call: t_N and both in-plane targets at -3.856 kPa (relaxed to t_N), 1.56 um of slip.
InterfaceInput<double> the_call() {
    const double t_n = -3.85553686636442;
    return {t_n, 1.562500000000153e-06, 0.0, t_n, t_n, 0.0};
}

InterfaceSettings the_run_settings(int line_search) {
    InterfaceSettings s; // the scene's rough pair: novel 3D, adaptive, rate Jacobian throughout
    s.adaptive = true;
    s.shear_band_thickness = 0.006;
    s.work_model_substeps = 8.0;
    s.work_newton_iterations = 4.0;
    s.newton_line_search = line_search;
    return s;
}

bool same_bits(double a, double b) {
    return std::memcmp(&a, &b, sizeof a) == 0;
}

} // namespace

TEST(InterfaceNewtonLineSearch, BandOnItsConeFailsWithoutAndEndsWithBacktracking) {
    const auto mp = karlsruhe_sanisand(1.0);
    const auto in = the_call();
    const auto plain = direct_update<Sanisand>(mp, the_run_settings(0), band_on_its_cone(), in);
    // Measured: 16 sub-increments, then the second try also fails; residual 0.0123.
    EXPECT_EQ(plain.stats.status, lane_status::failed);
    EXPECT_EQ(plain.stats.newton_fallbacks, 1.0);

    const InterfaceSettings s = the_run_settings(4);
    const auto r = direct_update<Sanisand>(mp, s, band_on_its_cone(), in);
    ASSERT_EQ(r.stats.status, lane_status::ok);
    EXPECT_EQ(r.stats.newton_fallbacks, 0.0); // measured: 58 sub-increments, 471 evaluations
    EXPECT_LT(r.stats.model_substeps, 2.0e4); // measured 3 197

    // The reference: the paper's fixed sub-increments, five times finer, with backtracking (the
    // plain fixed run meets the same kink).
    InterfaceSettings fine = the_run_settings(4);
    fine.adaptive = false;
    fine.max_subincrement = 1.0e-6;
    const auto ref = direct_update<Sanisand>(mp, fine, band_on_its_cone(), in);
    ASSERT_EQ(ref.stats.status, lane_status::ok);
    const double scale = std::abs(in.t_N);
    for (int k = 0; k < 5; ++k) {
        EXPECT_LT(std::abs(r.st.y[k] - ref.st.y[k]), 5.0 * s.adaptive_tolerance * scale)
            << "stress " << k << ": " << r.st.y[k] << " against " << ref.st.y[k];
    }
    // Eqs. 18-20: the normal stresses end at their targets.
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(r.st.y[k], in.t_N, 2.0 * s.tolerance * std::sqrt(3.0) * scale) << k;
    }
}

// A lane whose Newton lowers its residual in every step never backtracks: the same bits and
// the same number of evaluations with backtracking on and off.
TEST(InterfaceNewtonLineSearch, ContractingCallsAreUntouched) {
    const auto mp = karlsruhe_sanisand(1.0);
    for (const double v : {0.0, 3.0, 7.0}) {
        const auto in = ordinary_sanisand_call(v);
        const auto off =
            direct_update<Sanisand>(mp, the_run_settings(0), ordinary_sanisand_band(), in);
        const auto on =
            direct_update<Sanisand>(mp, the_run_settings(4), ordinary_sanisand_band(), in);
        ASSERT_EQ(off.stats.status, lane_status::ok) << v;
        EXPECT_EQ(on.stats.evaluations, off.stats.evaluations) << v;
        for (int k = 0; k < NS; ++k) {
            EXPECT_TRUE(same_bits(on.st.y[k], off.st.y[k])) << v << " entry " << k;
        }
        EXPECT_TRUE(same_bits(on.st.eps_n, off.st.eps_n)) << v;
    }
}

// The backtracking lane in a batch of ordinary ones: it ends where the scalar path ends, and
// its neighbours give the bits they give without backtracking (it is a per-lane mask).
TEST(InterfaceNewtonLineSearch, BatchLaneMatchesScalarAndSparesItsNeighbours) {
    if (W < 2) {
        GTEST_SKIP() << "scalar build";
    }
    const auto mp = karlsruhe_sanisand(1.0);
    const std::size_t hard = 1;
    auto lane_state = [&](std::size_t l) {
        return l == hard ? band_on_its_cone() : ordinary_sanisand_band();
    };
    auto lane_input = [&](std::size_t l) {
        return l == hard ? the_call() : ordinary_sanisand_call(static_cast<double>(l));
    };
    auto run = [&](const InterfaceSettings& s) {
        auto r = batched_update<Sanisand>(mp, s, lane_state, lane_input);
        return std::pair{r.st, r.stats};
    };
    const auto [with, with_stats] = run(the_run_settings(4));
    const auto [without, without_stats] = run(the_run_settings(0));
    const auto scalar =
        direct_update<Sanisand>(mp, the_run_settings(4), band_on_its_cone(), the_call());
    ASSERT_EQ(simd::lane(with_stats.status, hard), lane_status::ok);
    EXPECT_EQ(simd::lane(without_stats.status, hard), lane_status::failed);
    for (int k = 0; k < 5; ++k) {
        EXPECT_NEAR(simd::lane(with.y[k], hard), scalar.st.y[k],
                    the_run_settings(4).adaptive_tolerance * std::abs(the_call().t_N))
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
