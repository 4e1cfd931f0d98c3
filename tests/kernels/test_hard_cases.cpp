// Hard cases of the guarded hypoplastic update (material_update<Hypoplasticity, T>): zero,
// near-zero and tensile stress, void ratios outside [e_d, e_i], huge increments, a strain
// reversal at every step, NaN and inf in the state or increment. Each must end in a defined
// status of model_api.hpp with a usable state:
//   ok (1)          integrated within tolerance;
//   unreliable (0)  a safeguard acted (start below the pressure floor, tension cut-off,
//                   smallest substep taken without meeting the tolerance);
//   failed (-1)     no usable result: the state is returned exactly as it came in.
// Scalar path and SIMD path, and a bad lane must not change its neighbours' results by a bit.

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "kernels/parameter_sets.hpp"
#include "tests/kernels/element_paths.hpp"

namespace ifsim {
namespace {

using test::HypoState;

constexpr double nan = std::numeric_limits<double>::quiet_NaN();
constexpr double inf = std::numeric_limits<double>::infinity();

HypoplasticityParams prepared(HypoplasticityParams p, bool igs) {
    p.intergranular_strain = igs;
    p.prepare();
    return p;
}

struct Case {
    std::string name;
    HypoState y;
    Sym<double> deps;
};

bool finite_input(const Case& c) {
    for (const double v : c.y) {
        if (!std::isfinite(v)) {
            return false;
        }
    }
    for (const double v : c.deps) {
        if (!std::isfinite(v)) {
            return false;
        }
    }
    return true;
}

std::vector<Case> hard_cases(const HypoplasticityParams& p) {
    const Sym<double> comp = test::isotropic(-1e-4 / 3.0);
    const Sym<double> ext = test::isotropic(1e-4 / 3.0);
    const Sym<double> shear{0.0, 0.0, 0.0, 1e-4, 0.0, 0.0};
    const Sym<double> mixed{-0.6e-4, 0.5e-4, 0.2e-4, 0.3e-4, -0.2e-4, 0.1e-4};
    const Sym<double> incs[] = {comp, ext, shear, mixed};
    const char* inc_names[] = {"compression", "extension", "shear", "mixed"};

    struct Start {
        const char* name;
        Sym<double> sig;
        double e;
        Sym<double> h;
    };
    const double e_mid = 0.5 * (test::bauer(p, p.e_c0, 100.0) + test::bauer(p, p.e_d0, 100.0));
    const Sym<double> h_half{0.5 * p.R, 0.0, 0.0, 0.0, 0.0, 0.0};
    const Sym<double> iso100 = test::isotropic(-100.0);
    const std::vector<Start> starts = {
        {"zero stress", voigt::zero<double>(), 0.7, {}},
        {"1e-9 kPa", test::isotropic(-1e-9), 0.7, {}},
        {"at the floor", test::isotropic(-1e-3), 0.7, {}},
        {"1e-2 kPa", test::isotropic(-1e-2), 0.7, h_half},
        {"near-zero deviator", {-1e-4, 1e-4, 0.0, 1e-4, 0.0, 0.0}, 0.7, {}},
        {"isotropic tension", test::isotropic(50.0), 0.7, {}},
        {"uniaxial tension p < 0", {20.0, -5.0, -5.0, 0.0, 0.0, 0.0}, 0.7, {}},
        {"tensile principal p > 0", {20.0, -100.0, -100.0, 0.0, 0.0, 0.0}, 0.7, {}},
        {"zero principal", {0.0, -100.0, -100.0, 0.0, 0.0, 0.0}, 0.7, {}},
        {"pressure 1e7 kPa", test::isotropic(-1e7), 0.3, {}},
        {"e below e_d", iso100, 0.3, {}},
        {"e above e_i", iso100, 1.6, h_half},
        {"e = e_d", iso100, test::bauer(p, p.e_d0, 100.0), {}},
        {"e = e_i", iso100, test::bauer(p, p.e_i0, 100.0), {}},
        {"e = 1e-9", iso100, 1e-9, {}},
        {"e = 0", iso100, 0.0, {}},
        {"e < 0", iso100, -0.1, {}},
        {"|h| = 2R", iso100, e_mid, {2.0 * p.R, 0.0, 0.0, 0.0, 0.0, 0.0}},
        {"NaN stress", {nan, -100.0, -100.0, 0.0, 0.0, 0.0}, e_mid, {}},
        {"inf stress", {-100.0, -inf, -100.0, 0.0, 0.0, 0.0}, e_mid, {}},
        {"NaN e", iso100, nan, {}},
        {"inf e", iso100, inf, {}},
        {"NaN h", iso100, e_mid, {0.0, 0.0, nan, 0.0, 0.0, 0.0}},
    };
    std::vector<Case> cases;
    for (const Start& st : starts) {
        for (int k = 0; k < 4; ++k) {
            cases.push_back({std::string(st.name) + " / " + inc_names[k],
                             test::hypo_state(st.sig, st.e, st.h), incs[k]});
            // One huge increment (1e-2) of each kind as well.
            cases.push_back({std::string(st.name) + " / huge " + inc_names[k],
                             test::hypo_state(st.sig, st.e, st.h), voigt::scale(incs[k], 100.0)});
        }
        cases.push_back({std::string(st.name) + " / zero increment",
                         test::hypo_state(st.sig, st.e, st.h), voigt::zero<double>()});
    }
    const HypoState ok_state = test::hypo_state(iso100, e_mid);
    cases.push_back({"NaN increment", ok_state, {nan, 0.0, 0.0, 0.0, 0.0, 0.0}});
    cases.push_back({"inf increment", ok_state, {0.0, 0.0, 0.0, inf, 0.0, 0.0}});
    cases.push_back({"-inf increment", ok_state, {0.0, -inf, 0.0, 0.0, 0.0, 0.0}});
    cases.push_back({"huge random increment", ok_state,
                     voigt::scale(Sym<double>{-0.5, 0.3, 0.1, 0.6, -0.4, 0.2}, 1e-2)});
    return cases;
}

// The contract of one update, whatever the input.
void expect_defined(const HypoplasticityParams& p, const IntegrationSettings& s, const Case& c,
                    const HypoState& out, const UpdateStats<double>& st, const char* path) {
    SCOPED_TRACE(c.name + " (" + path + ")");
    ASSERT_TRUE(st.status == lane_status::ok || st.status == lane_status::unreliable ||
                st.status == lane_status::failed)
        << st.status;
    EXPECT_TRUE(std::isfinite(st.substeps) && std::isfinite(st.rejected) &&
                std::isfinite(st.rate_evaluations));
    if (!finite_input(c)) {
        EXPECT_EQ(st.status, lane_status::failed);
    }
    if (st.status == lane_status::failed) {
        // Returned exactly as it came in (NaN stays NaN: nothing usable can be invented).
        for (int k = 0; k < Hypoplasticity::n_state; ++k) {
            EXPECT_TRUE(out[k] == c.y[k] || (std::isnan(out[k]) && std::isnan(c.y[k]))) << k;
        }
        return;
    }
    for (int k = 0; k < Hypoplasticity::n_state; ++k) {
        ASSERT_TRUE(std::isfinite(out[k])) << "entry " << k;
    }
    EXPECT_GE(mean_pressure(stress_of(out)), s.min_pressure * (1.0 - 1e-12));
    EXPECT_GT(out[state_index::void_ratio], 0.0);
    if (p.intergranular_strain) {
        EXPECT_LE(voigt::norm(sym_at(out, Hypoplasticity::h_index)), p.R * (1.0 + 1e-12));
    }
    if (mean_pressure(stress_of(c.y)) < s.min_pressure) {
        EXPECT_EQ(st.status, lane_status::unreliable) << "start below the pressure floor";
    }
}

TEST(HardCases, EveryCaseEndsInADefinedStatusScalarAndSimd) {
    const IntegrationSettings s;
    for (const bool igs : {false, true}) {
        const HypoplasticityParams p = prepared(parameter_sets::hypoplasticity_karlsruhe(), igs);
        const std::vector<Case> cases = hard_cases(p);
        int counts[3] = {0, 0, 0};
        std::vector<HypoState> scalar_out;
        std::vector<double> scalar_status;
        for (const Case& c : cases) {
            HypoState y = c.y;
            const auto st = test::strain_step(p, s, y, c.deps);
            expect_defined(p, s, c, y, st, "scalar");
            ++counts[static_cast<int>(st.status) + 1];
            scalar_out.push_back(y);
            scalar_status.push_back(st.status);
        }
        // The same cases as lanes of SIMD batches (the last batch padded with the first case).
        for (std::size_t b = 0; b < cases.size(); b += simd::lanes) {
            std::vector<HypoState> ys(simd::lanes);
            std::vector<Sym<double>> ds(simd::lanes);
            for (std::size_t l = 0; l < simd::lanes; ++l) {
                const Case& c = cases[b + l < cases.size() ? b + l : 0];
                ys[l] = c.y;
                ds[l] = c.deps;
            }
            auto yb = test::to_batch(ys);
            UpdateStats<simd::batch> stb;
            material_update<Hypoplasticity, simd::batch>(p, s, SubstepControl<simd::batch>{}, yb,
                                                         test::sym_batch(ds), stb);
            for (std::size_t l = 0; l < simd::lanes && b + l < cases.size(); ++l) {
                const HypoState out = test::lane_of(yb, l);
                const auto st = test::stats_lane(stb, l);
                expect_defined(p, s, cases[b + l], out, st, "SIMD");
                EXPECT_EQ(st.status, scalar_status[b + l]) << cases[b + l].name;
            }
        }
        RecordProperty(igs ? "ok_unreliable_failed_igs" : "ok_unreliable_failed",
                       std::to_string(counts[2]) + " " + std::to_string(counts[1]) + " " +
                           std::to_string(counts[0]));
    }
}

// Below e_d the pyknotropy factor is 0 (the guard of the notes, section 4): N vanishes and the
// rate is linear in D, so reversing D reverses the stress rate exactly.
TEST(HardCases, VoidRatioBelowEdGivesTheLinearResponse) {
    const IntegrationSettings s;
    const HypoplasticityParams p = prepared(parameter_sets::hypoplasticity_l4c(), false);
    const HypoState y = test::hypo_state({-120.0, -90.0, -100.0, 10.0, 0.0, -5.0}, 0.5);
    const Sym<double> d{-1e-4, 0.3e-4, 0.2e-4, 0.5e-4, 0.0, 0.1e-4};
    const HypoState up = Hypoplasticity::euler_increment(p, s, y, d);
    const HypoState down = Hypoplasticity::euler_increment(p, s, y, voigt::scale(d, -1.0));
    for (int i = 0; i < 6; ++i) {
        EXPECT_NEAR(up[i], -down[i], 1e-13 * std::fabs(up[i]) + 1e-15);
    }
    // Just above e_d, f_d > 0 and the response is not symmetric.
    const HypoState y2 = test::hypo_state(stress_of(y), 0.9);
    const HypoState up2 = Hypoplasticity::euler_increment(p, s, y2, d);
    const HypoState down2 = Hypoplasticity::euler_increment(p, s, y2, voigt::scale(d, -1.0));
    EXPECT_GT(std::fabs(up2[0] + down2[0]), 1e-3 * std::fabs(up2[0]));
}

// A NaN lane (and a slow lane with a huge increment) among valid lanes leaves the valid lanes'
// results bitwise identical to running each of them alone (a batch of copies of itself).
TEST(HardCases, BadAndSlowLanesDoNotDisturbTheirNeighbours) {
    const IntegrationSettings s;
    for (const bool igs : {false, true}) {
        const HypoplasticityParams p = prepared(parameter_sets::hypoplasticity_l4c(), igs);
        std::vector<HypoState> ys(simd::lanes);
        std::vector<Sym<double>> ds(simd::lanes);
        for (std::size_t l = 0; l < simd::lanes; ++l) {
            const double pm = 20.0 + 40.0 * static_cast<double>(l);
            ys[l] = test::hypo_state({-pm, -0.8 * pm, -0.9 * pm, 0.1 * pm, 0.0, 0.0},
                                     test::bauer(p, p.e_c0, pm) * 0.95,
                                     {0.0, 0.0, 0.0, 0.3 * p.R, 0.0, 0.0});
            ds[l] = {-1e-4, 0.2e-4, 0.3e-4, 1e-4 * static_cast<double>(l % 3), 0.0, 0.0};
        }
        // Lane 1: NaN in the state; lane 2: NaN in the increment; lane 3: a huge increment.
        ys[1][state_index::void_ratio] = nan;
        ds[2][3] = nan;
        ds[3] = voigt::scale(Sym<double>{-0.5, 0.3, 0.1, 0.6, -0.4, 0.2}, 2e-2);

        auto yb = test::to_batch(ys);
        UpdateStats<simd::batch> stb;
        material_update<Hypoplasticity, simd::batch>(p, s, SubstepControl<simd::batch>{}, yb,
                                                     test::sym_batch(ds), stb);
        EXPECT_EQ(simd::lane(stb.status, 1), lane_status::failed);
        EXPECT_EQ(simd::lane(stb.status, 2), lane_status::failed);
        EXPECT_GT(simd::lane(stb.substeps, 3), 3.0 * simd::lane(stb.substeps, 0));
        for (std::size_t l = 0; l < simd::lanes; ++l) {
            if (l == 1 || l == 2) {
                continue;
            }
            auto alone = test::to_batch(std::vector<HypoState>(simd::lanes, ys[l]));
            UpdateStats<simd::batch> sta;
            material_update<Hypoplasticity, simd::batch>(
                p, s, SubstepControl<simd::batch>{}, alone,
                test::sym_batch(std::vector<Sym<double>>(simd::lanes, ds[l])), sta);
            for (int k = 0; k < Hypoplasticity::n_state; ++k) {
                EXPECT_EQ(simd::lane(yb[k], l), simd::lane(alone[k], 0))
                    << "lane " << l << " entry " << k;
            }
            EXPECT_EQ(simd::lane(stb.substeps, l), simd::lane(sta.substeps, 0));
            EXPECT_EQ(simd::lane(stb.status, l), simd::lane(sta.status, 0));
        }
    }
}

// Runaway: a lane that does not finish within max_substeps is reported failed and returned as
// it came in; a lane of the same batch that finished in time keeps its result.
TEST(HardCases, SubstepLimitFailsTheLaneAndRestoresIt) {
    IntegrationSettings s;
    s.tolerance = 1e-6;
    s.max_substeps = 5;
    const HypoplasticityParams p = prepared(parameter_sets::hypoplasticity_karlsruhe(), true);
    const HypoState y0 = test::hypo_state(test::isotropic(-100.0), 0.7);
    const Sym<double> huge = voigt::scale(Sym<double>{-0.5, 0.3, 0.1, 0.6, -0.4, 0.2}, 1e-2);
    HypoState y = y0;
    const auto st = test::strain_step(p, s, y, huge);
    EXPECT_EQ(st.status, lane_status::failed);
    for (int k = 0; k < Hypoplasticity::n_state; ++k) {
        EXPECT_EQ(y[k], y0[k]);
    }
    std::vector<HypoState> ys(simd::lanes, y0);
    std::vector<Sym<double>> ds(simd::lanes, voigt::zero<double>());
    ds[0] = huge;
    auto yb = test::to_batch(ys);
    UpdateStats<simd::batch> stb;
    material_update<Hypoplasticity, simd::batch>(p, s, SubstepControl<simd::batch>{}, yb,
                                                 test::sym_batch(ds), stb);
    EXPECT_EQ(simd::lane(stb.status, 0), lane_status::failed);
    for (std::size_t l = 1; l < simd::lanes; ++l) {
        EXPECT_EQ(simd::lane(stb.status, l), lane_status::ok);
        EXPECT_EQ(simd::lane(stb.substeps, l), 1.0);
    }
    for (int k = 0; k < Hypoplasticity::n_state; ++k) {
        EXPECT_EQ(simd::lane(yb[k], 0), y0[k]);
    }
}

// One huge increment (1e-2) integrates the same path as 100 small ones, to the tolerance: the
// substepping, not the caller, resolves the nonlinearity.
TEST(HardCases, HugeIncrementEqualsManySmallOnes) {
    IntegrationSettings s;
    s.tolerance = 1e-5;
    const Sym<double> d = voigt::scale(Sym<double>{-0.6, 0.2, 0.25, 0.5, -0.2, 0.1}, 1e-2);
    for (const bool igs : {false, true}) {
        const HypoplasticityParams p = prepared(parameter_sets::hypoplasticity_karlsruhe(), igs);
        const HypoState y0 = test::hypo_state({-100.0, -80.0, -90.0, 0.0, 5.0, 0.0},
                                              test::bauer(p, p.e_c0, 90.0) * 0.97);
        HypoState one = y0, many = y0;
        EXPECT_EQ(test::strain_step(p, s, one, d).status, lane_status::ok);
        for (int k = 0; k < 100; ++k) {
            EXPECT_EQ(test::strain_step(p, s, many, voigt::scale(d, 0.01)).status, lane_status::ok);
        }
        const double diff =
            voigt::norm(voigt::sub(stress_of(one), stress_of(many))) / voigt::norm(stress_of(many));
        EXPECT_LT(diff, s.tolerance) << "igs " << igs;
        EXPECT_NEAR(one[6], many[6], 1e-10);
    }
}

// A strain reversal at every step, 400 steps.
// With intergranular strain and amplitudes well inside the elastic range R, each reversal is
// answered by m_R L (hypoelastic), so the state shakes down: after an even number of steps it
// is back at the start up to the second-order drift of L along the path.
// Without intergranular strain, hypoplasticity accumulates (the known over-prediction of
// ratcheting): the pressure decays and at larger amplitudes the tension cut-off acts; the
// statuses stay defined and the state usable.
TEST(HardCases, StrainReversalAtEveryStep) {
    const IntegrationSettings s;
    const HypoState y0 = test::hypo_state({-100.0, -80.0, -80.0, 5.0, 0.0, 0.0}, 0.77);
    const Sym<double> shear{0.0, 0.0, 0.0, 1.0, 0.0, 0.0};
    const Sym<double> mixed{-1.0, 0.2, 0.2, 0.3, 0.0, 0.0};
    for (const bool igs : {false, true}) {
        const HypoplasticityParams p = prepared(parameter_sets::hypoplasticity_karlsruhe(), igs);
        for (const double amp : {1e-6, 1e-5, 1e-4, 1e-3}) {
            for (const Sym<double>& dir : {shear, mixed}) {
                HypoState y = y0;
                int unreliable = 0;
                for (int k = 0; k < 400; ++k) {
                    const Case c{"reversal", y, voigt::scale(dir, k % 2 == 0 ? amp : -amp)};
                    const auto st = test::strain_step(p, s, y, c.deps);
                    expect_defined(p, s, c, y, st, "scalar");
                    ASSERT_NE(st.status, lane_status::failed);
                    unreliable += st.status == lane_status::unreliable ? 1 : 0;
                }
                if (igs && amp <= 0.2 * p.R) {
                    EXPECT_EQ(unreliable, 0);
                    const double drift = voigt::norm(voigt::sub(stress_of(y), stress_of(y0))) /
                                         voigt::norm(stress_of(y0));
                    EXPECT_LT(drift, 1e-3) << "amplitude " << amp;
                    EXPECT_NEAR(y[6], y0[6], 1e-9);
                }
                if (!igs && amp == 1e-5) {
                    // Accumulation without intergranular strain: p falls by more than half.
                    EXPECT_LT(mean_pressure(stress_of(y)), 0.5 * mean_pressure(stress_of(y0)));
                }
            }
        }
    }
}

} // namespace
} // namespace ifsim
