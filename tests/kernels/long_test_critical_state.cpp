// Long runs (label "long"): critical state in drained triaxial compression WITH intergranular
// strain (the orientation of h is a stiff mode, so the substeps stay ~R and the run costs
// ~1e5 substeps), the very slow approach at small roughness kappa = 0.35, and a convergence
// study of the adaptive integration over a cyclic path with intergranular strain.

#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "kernels/parameter_sets.hpp"
#include "tests/kernels/element_paths.hpp"

namespace ifsim {
namespace {

using test::HypoState;

HypoplasticityParams prepared(HypoplasticityParams p, bool igs, double kappa = 1.0) {
    p.intergranular_strain = igs;
    p.roughness = kappa;
    p.prepare();
    return p;
}

TEST(LongCriticalState, DrainedTriaxialWithIntergranularStrain) {
    IntegrationSettings s;
    s.tolerance = 1e-5;
    for (const auto& base :
         {parameter_sets::hypoplasticity_l4c(), parameter_sets::hypoplasticity_karlsruhe()}) {
        const HypoplasticityParams p = prepared(base, true);
        const double Mc = test::critical_ratio_compression(p.phi_c);
        for (const double density : {0.85, 1.05}) {
            HypoState y =
                test::hypo_state(test::isotropic(-100.0), density * test::bauer(p, p.e_c0, 100.0));
            const auto r = test::drained_triaxial(p, s, y, 10.0, 500);
            ASSERT_TRUE(r.ok) << "Newton failed at step " << r.steps;
            const double pm = mean_pressure(stress_of(y));
            const double ratio = test::deviatoric_q(stress_of(y)) / pm;
            const double e_rel = y[6] / test::bauer(p, p.e_c0, pm) - 1.0;
            std::printf("[measured] IGS drained triaxial phi_c %.1f deg, e0/e_c %.2f: "
                        "q/p/M_c - 1 = %.2e, e/e_c - 1 = %.2e, |h|/R = %.6f\n",
                        p.phi_c / parameter_sets::deg, density, ratio / Mc - 1.0, e_rel,
                        voigt::norm(sym_at(y, 7)) / p.R);
            EXPECT_NEAR(ratio, Mc, 2e-5 * Mc);
            EXPECT_NEAR(e_rel, 0.0, 2e-5);
        }
    }
}

// kappa = 0.35 (the smooth steel segments of the paper's large-scale test): the deviation
// decays like exp(-0.063 eps), so the run shears to 300.
TEST(LongCriticalState, SmallRoughnessDrainedTriaxial) {
    IntegrationSettings s;
    s.tolerance = 1e-6;
    const double kappa = 0.35;
    const HypoplasticityParams p = prepared(parameter_sets::hypoplasticity_l4c(), false, kappa);
    HypoState y = test::hypo_state(test::isotropic(-100.0), test::bauer(p, p.e_c0, 100.0));
    ASSERT_TRUE(test::drained_triaxial(p, s, y, 300.0, 6000).ok);
    const double pm = mean_pressure(stress_of(y));
    const double Mk = test::critical_ratio_compression(kappa * p.phi_c);
    const double ratio = test::deviatoric_q(stress_of(y)) / pm;
    const double e_rel = y[6] / test::bauer(p, p.e_c0, pm) - 1.0;
    std::printf("[measured] kappa 0.35: q/p/M_k - 1 = %.2e, e/e_c - 1 = %.2e\n", ratio / Mk - 1,
                e_rel);
    EXPECT_NEAR(ratio, Mk, 2e-6 * Mk);
    EXPECT_NEAR(e_rel, 0.0, 2e-6);
}

// Global error of a cyclic strain path with intergranular strain (20 reversals of +-2e-3 in
// mixed shear/volumetric directions, 10 increments per quarter cycle) against the same path at
// tolerance 1e-10: the error falls in proportion to the tolerance.
HypoState cyclic(const HypoplasticityParams& p, double tol, double* substeps) {
    IntegrationSettings s;
    s.tolerance = tol;
    s.max_substeps = 1 << 24;
    HypoState y = test::hypo_state({-100.0, -70.0, -75.0, 4.0, 0.0, 0.0},
                                   test::bauer(p, p.e_c0, 80.0) * 0.95);
    const Sym<double> d = voigt::scale(Sym<double>{-0.3, 0.1, 0.1, 1.0, 0.2, 0.0}, 2e-4);
    const int signs[] = {1, -1, -1, 1};
    *substeps = 0.0;
    for (int cycle = 0; cycle < 5; ++cycle) {
        for (const int sgn : signs) {
            for (int k = 0; k < 10; ++k) {
                const auto st = test::strain_step(p, s, y, voigt::scale(d, double(sgn)));
                EXPECT_NE(st.status, lane_status::failed);
                *substeps += st.substeps;
            }
        }
    }
    return y;
}

TEST(LongIntegration, CyclicPathErrorFollowsTheTolerance) {
    const HypoplasticityParams p = prepared(parameter_sets::hypoplasticity_karlsruhe(), true);
    double sub_ref = 0.0;
    const HypoState ref = cyclic(p, 1e-10, &sub_ref);
    std::vector<double> tols, errs;
    for (double tol = 1e-2; tol >= 0.99e-7; tol /= 10.0) {
        double sub = 0.0;
        const HypoState y = cyclic(p, tol, &sub);
        const double err =
            voigt::norm(voigt::sub(stress_of(y), stress_of(ref))) / voigt::norm(stress_of(ref));
        std::printf("[measured] cyclic IGS path: tol %.0e  error %.3e  substeps %.0f\n", tol, err,
                    sub);
        tols.push_back(tol);
        errs.push_back(err);
    }
    std::printf("[measured] reference substeps %.0f\n", sub_ref);
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    const double n = static_cast<double>(tols.size());
    for (std::size_t i = 0; i < tols.size(); ++i) {
        const double lx = std::log(tols[i]), ly = std::log(errs[i]);
        sx += lx;
        sy += ly;
        sxx += lx * lx;
        sxy += lx * ly;
    }
    const double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    std::printf("[measured] observed order of the global error in the tolerance: %.3f\n", slope);
    EXPECT_GT(slope, 0.8);
    EXPECT_LT(slope, 1.3);
    EXPECT_LT(errs.back(), 1e-6);
}

} // namespace
} // namespace ifsim
