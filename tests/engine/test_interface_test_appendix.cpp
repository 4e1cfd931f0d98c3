// The paper's appendices at point level (run_interface_test, monotonic CNL test of §5.1).
//
// Appendix C: with the interface and the sample the same material in the same state (kappa = 1),
// the novel formulation keeps eps_p1 = eps_p2 ~ 0 while both follow the same strain path, and
// the Stutz formulation initialised from the continuum coincides with it.
//
// Appendix B: outer Newton iterations of the test's step equations with the interface Jacobian
// of Eq. 37 (perturbation), of Eqs. 39-40 (full perturbation) and of Eq. B3 (analytical).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#define IFSIM_TEST_ENGINE_HELPERS
#include "tests/engine/interface_fixtures.hpp"

using namespace ifsim;
using namespace ifsim::test;

// kappa = 1, 1 mm in 20 steps (the peak of this discretisation is at ~1.6 mm). Measured:
// |eps_p| <= 3.8e-6 up to 0.9 mm and 7.8e-6 at 1 mm where the response starts to soften;
// novel and Stutz t_t1 within 2.8e-3 kPa up to 0.9 mm and 7.3e-3 kPa at 1 mm; the Stutz in-plane
// stresses within 0.01 kPa of the sample's ("almost no jump", Appendix C). For contrast, with
// kappa = 0.9 the interface is a different material and eps_p1 exceeds 1e-3 at 0.5 mm (see
// test_interface_test.cpp).
TEST(InterfaceTestAppendixC, IdenticalMaterialsKeepInPlaneStrainsZero) {
    InterfaceTestSpec novel = l4c_spec(InterfaceFormulation::novel, 1.0);
    novel.stages = {{20, 1.0e-3, 0.0}};
    InterfaceTestSpec stutz = novel;
    stutz.contact.interface.formulation = InterfaceFormulation::stutz;
    const DriverRun a = run_driver(novel);
    const DriverRun b = run_driver(stutz);
    ASSERT_TRUE(a.result.ok) << a.result.reason;
    ASSERT_TRUE(b.result.ok) << b.result.reason;
    ASSERT_EQ(a.rows.size(), b.rows.size());
    for (std::size_t k = 0; k < a.rows.size(); ++k) {
        const InterfaceRow& ra = a.rows[k];
        const InterfaceRow& rb = b.rows[k];
        SCOPED_TRACE(ra.step);
        const double eps_bound = ra.u_t1 <= 0.9e-3 ? 1.0e-5 : 3.0e-5;
        EXPECT_LT(std::abs(ra.eps_p1), eps_bound);
        EXPECT_LT(std::abs(ra.eps_p2), eps_bound);
        // The series system carries one shear stress, so both formulations must agree to the
        // step tolerance (0.01 kPa) plus the effect of the tiny eps_p.
        EXPECT_NEAR(ra.t_t1, rb.t_t1, 0.02);
        EXPECT_NEAR(ra.u_n, rb.u_n, 1.0e-7);
        EXPECT_NEAR(rb.s_p1, rb.sample_s22, 0.05);
        // Same material, same stress: the interface's shear strain is the sample's
        // (2 eps_12 = (u_t - slip) / H) up to the step size. Within a step Algorithm 1 moves the
        // in-plane targets along a straight line while the sample's sigma_22 follows its own
        // curve, so the two strain paths differ at second order in the step: measured -0.33 %
        // (20 steps per mm), -0.077 % (40), -0.020 % (80) up to 0.9 mm; -0.87 % at 1 mm with 20
        // steps, where the tangent stiffness drops.
        if (k > 0) {
            const double sample_gamma = (ra.u_t1 - ra.slip1) / novel.height;
            const double bound = ra.u_t1 <= 0.9e-3 ? 1.0e-2 : 2.0e-2;
            EXPECT_NEAR(ra.gamma1, sample_gamma, bound * sample_gamma);
        }
    }
    EXPECT_GT(a.rows.back().t_t1, 70.0);
}

// Appendix B: the first 20 steps of the monotonic CNL test (kappa = 0.9, through the peak at
// 0.45 mm). Counted outer Newton iterations (measured, novel formulation; the counts do not
// depend on the sub-increment size between 5e-5 and 4e-4, so the coarsest is used):
//   Eq. 37 perturbation        33  (3 2 2 2 2 2 2 2 2 4, then 1 per step)
//   Eqs. 39-40 full perturb.   70  (12 7 6 6 6 6 5 3 5 4, then 1 per step)
//   Eq. B3 analytical         347  and 3 step cuts (118 iterations in step 9 alone)
// The paper finds the full scheme slightly better than Eq. 37; here it is worse, because its
// columns are about twice the derivative of the update (test_contact_jacobian.cpp).
TEST(InterfaceTestAppendixB, PerturbationNeedsFewerIterationsThanAnalytical) {
    long counts[3] = {0, 0, 0};
    long cuts[3] = {0, 0, 0};
    const ContactJacobian schemes[3] = {ContactJacobian::perturbation,
                                        ContactJacobian::full_perturbation,
                                        ContactJacobian::analytical};
    for (int s = 0; s < 3; ++s) {
        InterfaceTestSpec spec = l4c_spec(InterfaceFormulation::novel);
        spec.contact.interface.max_subincrement = 4.0e-4;
        spec.contact.jacobian = schemes[s];
        spec.stages = {{20, 1.0e-3, 0.0}};
        const DriverRun r = run_driver(spec);
        counts[s] = r.result.ok ? r.result.counters.newton_iterations : 1000000;
        cuts[s] = r.result.counters.step_cuts;
        if (s == 0) {
            ASSERT_TRUE(r.result.ok) << r.result.reason;
            EXPECT_EQ(cuts[0], 0);
            // Quadratic outer Newton: at most 2 iterations per step on average.
            EXPECT_LE(counts[0], 40);
        }
    }
    std::printf("[ measured ] outer Newton iterations over 20 steps: Eq. 37 %ld, Eqs. 39-40 %ld, "
                "Eq. B3 %ld (step cuts %ld %ld %ld)\n",
                counts[0], counts[1], counts[2], cuts[0], cuts[1], cuts[2]);
    EXPECT_LT(counts[0], counts[2]);
    EXPECT_LT(2 * counts[0], counts[2]); // not a marginal difference
}
