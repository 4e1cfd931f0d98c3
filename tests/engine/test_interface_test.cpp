// The point-level simple interface shear test (run_interface_test, paper §5): sample in series
// with one interface point. Constant normal load keeps t_N, constant normal stiffness follows
// t_N = t_N0 - K u_n, the in-plane interface stresses follow the sample (novel) or jump (Stutz),
// the interface shear strain follows Eqs. 25-26 from the slip, and Coulomb friction sticks and
// slips exactly. Short runs (10-30 steps) with coarse sub-increments (1e-4) keep it fast; the
// paper's 5e-6 and the convergence in between are in long_test_interface_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#define IFSIM_TEST_ENGINE_HELPERS
#include "tests/engine/interface_fixtures.hpp"

using namespace ifsim;
using namespace ifsim::test;

// CNL (§5.1), 0.5 mm in 10 steps, through the peak (58.6 kPa at 0.45 mm): t_N stays at t_N0 in
// every row to the step tolerance, the interface's sigma_N to Algorithm 1's, and the novel
// formulation's in-plane stresses follow the sample's (Eqs. 19-20) while Stutz's do not.
TEST(InterfaceTest, ConstantNormalLoadKeepsTheNormalStress) {
    for (const auto f : {InterfaceFormulation::novel, InterfaceFormulation::stutz}) {
        InterfaceTestSpec spec = l4c_spec(f);
        spec.stages = {{10, 5.0e-4, 0.0}};
        const DriverRun r = run_driver(spec);
        ASSERT_TRUE(r.result.ok) << r.result.reason;
        ASSERT_EQ(r.rows.size(), 11u);
        EXPECT_EQ(r.result.counters.step_cuts, 0);
        const double tol_step = spec.newton_tolerance * 100.0;
        const double tol_alg1 = spec.contact.interface.tolerance * 100.0;
        double tau_max = 0.0;
        for (const auto& row : r.rows) {
            SCOPED_TRACE(row.step);
            EXPECT_NEAR(row.t_n, -100.0, tol_step);
            EXPECT_NEAR(row.s_n, -100.0, tol_alg1);
            EXPECT_NEAR(row.u_t1, 5.0e-5 * row.step, 1.0e-15);
            EXPECT_EQ(row.t_t2, row.sample_s13);
            EXPECT_NEAR(row.t_t2, 0.0, tol_step); // no shear along t2
            tau_max = std::max(tau_max, row.t_t1);
            if (f == InterfaceFormulation::novel) {
                // Measured |s_p1 - sigma_22| <= 4e-4 kPa, |s_n - t_N| <= 1e-3 kPa.
                EXPECT_NEAR(row.s_p1, row.sample_s22, tol_alg1);
                EXPECT_NEAR(row.s_p2, row.sample_s33, tol_alg1);
            } else {
                EXPECT_EQ(row.eps_p1, 0.0);
                EXPECT_EQ(row.eps_p2, 0.0);
            }
        }
        expect_shear_strain_follows_slip(r.rows);
        const InterfaceRow& last = r.rows.back();
        EXPECT_GT(tau_max, 40.0);
        EXPECT_LT(tau_max, 80.0);
        EXPECT_GT(last.slip1, 0.0);
        EXPECT_LT(last.slip1, last.u_t1);
        if (f == InterfaceFormulation::stutz) {
            // §5.1: with eps_p = 0 the interface's in-plane stresses run away from the sample's
            // (measured -99.8 against -87.4 kPa at 0.5 mm).
            EXPECT_LT(last.s_p1, last.sample_s22 - 5.0);
        } else {
            // kappa = 0.9 < 1: the interface is a different material from the sample, so
            // eps_p1 = eps_p2 = 0 does not "result by itself" (measured 5.5e-3 at 0.5 mm).
            EXPECT_GT(last.eps_p1, 1.0e-3);
        }
    }
}

// CNS (§5.2: t_N0 = -300 kPa, K = 400 kPa/mm), 0.5 mm out and back in 20 steps: in every row
// t_N = t_N0 - K u_n to the step tolerance (sample) and to Algorithm 1's (interface); the sand
// compacts, so t_N relaxes (measured from -300 to -236 kPa).
TEST(InterfaceTest, ConstantNormalStiffnessFollowsTheSpring) {
    for (const auto f : {InterfaceFormulation::novel, InterfaceFormulation::stutz}) {
        InterfaceTestSpec spec = l4c_spec(f, 0.9, -300.0);
        spec.control = NormalControl::constant_stiffness;
        spec.normal_stiffness = 4.0e5;
        spec.stages = {{10, 5.0e-4, 0.0}, {10, -5.0e-4, 0.0}};
        const DriverRun r = run_driver(spec);
        ASSERT_TRUE(r.result.ok) << r.result.reason;
        ASSERT_EQ(r.rows.size(), 21u);
        for (const auto& row : r.rows) {
            SCOPED_TRACE(row.step);
            const double t_N = -300.0 - 4.0e5 * row.u_n;
            EXPECT_NEAR(row.t_n, t_N, spec.newton_tolerance * std::abs(t_N));
            EXPECT_NEAR(row.s_n, t_N, spec.contact.interface.tolerance * std::abs(t_N));
        }
        expect_shear_strain_follows_slip(r.rows);
        const InterfaceRow& last = r.rows.back();
        EXPECT_LT(last.u_n, -1.0e-4);
        EXPECT_GT(last.t_n, -260.0);
        EXPECT_NEAR(last.u_t1, 0.0, 1.0e-15);
        EXPECT_LT(last.t_t1, -50.0); // reversed shear
    }
}

// Coulomb penalty friction in series with the sample: replaying the exact return mapping from
// the rows' slips reproduces the shear stress in every row (to the step tolerance): stick with
// t_t1 = k_t slip on first loading, slip with t_t1 = mu |t_N| exactly, elastic unloading after
// the reversal.
TEST(InterfaceTest, CoulombSticksAndSlipsExactly) {
    InterfaceTestSpec spec;
    spec.contact.interface.formulation = InterfaceFormulation::coulomb;
    spec.coulomb.friction_coefficient = 0.25;
    spec.coulomb.tangential_stiffness = 5.0e4;
    spec.sample_material = l4c(1.0);
    spec.sample_state = as_vector(hypo_state());
    spec.stages = {{20, 1.0e-3, 0.0}, {10, -5.0e-4, 0.0}};
    const DriverRun r = run_driver(spec);
    ASSERT_TRUE(r.result.ok) << r.result.reason;
    const double k_t = 5.0e4, limit = 0.25 * 100.0, tol = spec.newton_tolerance * 100.0;
    double tau = 0.0;
    int stick = 0, slip = 0;
    for (std::size_t k = 1; k < r.rows.size(); ++k) {
        const auto& row = r.rows[k];
        SCOPED_TRACE(row.step);
        EXPECT_NEAR(row.t_n, -100.0, tol);
        const double trial = tau + k_t * (row.slip1 - r.rows[k - 1].slip1);
        tau = std::abs(trial) > limit ? std::copysign(limit, trial) : trial;
        EXPECT_NEAR(row.t_t1, tau, tol);
        if (std::abs(trial) > limit) {
            ++slip;
            EXPECT_NEAR(row.t_t1, limit, tol);
        } else {
            ++stick;
            if (row.stage == 1) {
                EXPECT_NEAR(row.t_t1, k_t * row.slip1, tol);
            }
        }
    }
    EXPECT_GE(slip, 5);
    EXPECT_GE(stick, 15);
    EXPECT_LT(r.rows.back().t_t1, limit - 20.0); // unloaded after the reversal
}

// A continuum interface model that is not hypoplasticity: Sanisand (Karlsruhe sand) as
// interface and sample, CNL through the peak: t_N constant, Eqs. 19-20 for the novel
// formulation, Eq. 25-26 kinematics.
TEST(InterfaceTest, SanisandInterfaceUnderConstantNormalLoad) {
    for (const auto f : {InterfaceFormulation::novel, InterfaceFormulation::stutz}) {
        InterfaceTestSpec spec;
        spec.interface_material = karlsruhe_sanisand(0.9);
        spec.interface_state = as_vector(sanisand_state());
        spec.sample_material = karlsruhe_sanisand(1.0);
        spec.sample_state = as_vector(sanisand_state());
        spec.contact.interface.formulation = f;
        spec.contact.interface.max_subincrement = 1.0e-4;
        spec.stages = {{10, 5.0e-4, 0.0}};
        const DriverRun r = run_driver(spec);
        ASSERT_TRUE(r.result.ok) << r.result.reason;
        for (const auto& row : r.rows) {
            EXPECT_NEAR(row.t_n, -100.0, spec.newton_tolerance * 100.0);
            EXPECT_NEAR(row.s_n, -100.0, spec.contact.interface.tolerance * 100.0);
            if (f == InterfaceFormulation::novel) {
                EXPECT_NEAR(row.s_p1, row.sample_s22, spec.contact.interface.tolerance * 100.0);
            }
        }
        expect_shear_strain_follows_slip(r.rows);
        EXPECT_GT(r.rows.back().t_t1, 30.0);
    }
}
