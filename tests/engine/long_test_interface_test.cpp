// Convergence studies and long runs of the point-level interface test (label "long"):
// sub-increment size against a fine reference, the global step size, the paper's own
// sub-increment size, the post-peak branch of identical materials (Appendix C), Appendix B for
// the Stutz formulation and for Sanisand, and cyclic CNS shearing (§5.2).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#define IFSIM_TEST_ENGINE_HELPERS
#include "tests/engine/interface_fixtures.hpp"

using namespace ifsim;
using namespace ifsim::test;

namespace {

double t_t1_at_end(const InterfaceTestSpec& spec) {
    const DriverRun r = run_driver(spec);
    EXPECT_TRUE(r.result.ok) << r.result.reason;
    EXPECT_EQ(r.result.counters.step_cuts, 0);
    return r.rows.back().t_t1;
}

} // namespace

// t_t1 at u_t1 = 0.3 mm (6 steps, before the peak) against a reference with sub-increments of
// 1e-6. Measured errors (kPa):
//   max_subincrement   5e-5       2.5e-5     1.25e-5     order
//   novel             -4.15e-5   -1.12e-5   -2.93e-6     1.89, 1.94
//   Stutz             -2.70e-5   -7.64e-6   -2.04e-6     1.82, 1.90
// (Coarser sub-increments, 1e-4 .. 8e-4, are outside the asymptotic range: the error changes
// sign between 2e-4 and 1e-4.) Second order: each sub-increment is one Heun step of the model.
TEST(InterfaceTestConvergence, SubincrementSizeAgainstFineReference) {
    for (const auto f : {InterfaceFormulation::novel, InterfaceFormulation::stutz}) {
        InterfaceTestSpec spec = l4c_spec(f);
        spec.stages = {{6, 3.0e-4, 0.0}};
        spec.newton_tolerance = 1.0e-8;
        spec.contact.interface.max_subincrement = 1.0e-6;
        const double ref = t_t1_at_end(spec);
        double err[3];
        const double sizes[3] = {5.0e-5, 2.5e-5, 1.25e-5};
        for (int i = 0; i < 3; ++i) {
            spec.contact.interface.max_subincrement = sizes[i];
            err[i] = t_t1_at_end(spec) - ref;
        }
        std::printf(
            "[ measured ] form %d: t_t1 = %.8f kPa, errors %.3e %.3e %.3e, orders %.2f %.2f\n",
            static_cast<int>(f), ref, err[0], err[1], err[2], std::log2(err[0] / err[1]),
            std::log2(err[1] / err[2]));
        EXPECT_GT(std::abs(err[0]), std::abs(err[1]));
        EXPECT_GT(std::abs(err[1]), std::abs(err[2]));
        EXPECT_GT(std::log2(err[0] / err[1]), 1.5);
        EXPECT_GT(std::log2(err[1] / err[2]), 1.5);
        EXPECT_LT(std::abs(err[2]), 1.0e-5);
    }
}

// The global step (plate displacement per step) matters far more than the sub-increments: the
// in-plane targets move along a straight line within a step and d_s (Eq. 26) is taken at its
// start. t_t1 at 0.3 mm with 6, 12, 24, 48 steps: successive differences (measured, novel)
// 0.149, 0.0369, 0.00872, 0.00215 kPa -> order 2.0; Stutz 0.174, 0.0437, 0.0104, 0.00254.
TEST(InterfaceTestConvergence, GlobalStepSizeConvergesAtSecondOrder) {
    for (const auto f : {InterfaceFormulation::novel, InterfaceFormulation::stutz}) {
        InterfaceTestSpec spec = l4c_spec(f);
        spec.contact.interface.max_subincrement = 5.0e-5;
        spec.newton_tolerance = 1.0e-8;
        double t[4];
        const int steps[4] = {6, 12, 24, 48};
        for (int i = 0; i < 4; ++i) {
            spec.stages = {{steps[i], 3.0e-4, 0.0}};
            t[i] = t_t1_at_end(spec);
        }
        const double o1 = std::log2((t[1] - t[0]) / (t[2] - t[1]));
        const double o2 = std::log2((t[2] - t[1]) / (t[3] - t[2]));
        std::printf("[ measured ] form %d: t_t1 %.6f %.6f %.6f %.6f, orders %.2f %.2f\n",
                    static_cast<int>(f), t[0], t[1], t[2], t[3], o1, o2);
        EXPECT_GT(o1, 1.5);
        EXPECT_LT(o1, 2.5);
        EXPECT_GT(o2, 1.5);
        EXPECT_LT(o2, 2.5);
    }
}

// The paper's sub-increment size (5e-6) against the fast suite's 1e-4: 1 mm in 20 steps through
// the peak, every row.
TEST(InterfaceTestConvergence, PaperSubincrementSizeAgreesWithCoarse) {
    for (const auto f : {InterfaceFormulation::novel, InterfaceFormulation::stutz}) {
        InterfaceTestSpec spec = l4c_spec(f);
        spec.stages = {{20, 1.0e-3, 0.0}};
        const DriverRun coarse = run_driver(spec);
        spec.contact.interface.max_subincrement = 5.0e-6;
        const DriverRun paper = run_driver(spec);
        ASSERT_TRUE(coarse.result.ok);
        ASSERT_TRUE(paper.result.ok) << paper.result.reason;
        ASSERT_EQ(coarse.rows.size(), paper.rows.size());
        double worst = 0.0;
        for (std::size_t k = 0; k < coarse.rows.size(); ++k) {
            worst = std::max(worst, std::abs(coarse.rows[k].t_t1 - paper.rows[k].t_t1));
        }
        std::printf("[ measured ] form %d: max |t_t1(1e-4) - t_t1(5e-6)| = %.3e kPa, "
                    "sub-increments %.0f vs %.0f\n",
                    static_cast<int>(f), worst, coarse.result.counters.subincrements,
                    paper.result.counters.subincrements);
        EXPECT_LT(worst, 0.02); // the step tolerance is 0.01 kPa
    }
}

// Appendix C past the peak: kappa = 1, 4 mm in 400 steps. Before the series system bifurcates
// both parts follow one strain path and eps_p stays ~0 (measured 1.8e-7 up to 0.8 mm); at
// ~1.1 mm the deformation localises in one part (here the sample: the interface's eps_N stops
// at 1.1e-3 (novel) / 3.9e-3 (Stutz) while the sample keeps dilating to u_n/H = 2e-2), eps_p of
// the novel formulation grows to 2.5e-4 and the two formulations differ by up to 0.091 kPa.
// Which part localises depends on round-off-level details (with 6 um steps the novel
// formulation localised in the interface, docs/interface.md), so that is not asserted.
TEST(InterfaceTestAppendixC, PostPeakBranchOfIdenticalMaterials) {
    InterfaceTestSpec novel = l4c_spec(InterfaceFormulation::novel, 1.0);
    novel.stages = {{400, 4.0e-3, 0.0}};
    InterfaceTestSpec stutz = novel;
    stutz.contact.interface.formulation = InterfaceFormulation::stutz;
    const DriverRun a = run_driver(novel);
    const DriverRun b = run_driver(stutz);
    ASSERT_TRUE(a.result.ok) << a.result.reason;
    ASSERT_TRUE(b.result.ok) << b.result.reason;
    double eps_pre = 0.0, eps_post = 0.0, diff = 0.0, peak = 0.0;
    for (std::size_t k = 0; k < a.rows.size(); ++k) {
        const InterfaceRow& r = a.rows[k];
        const double e = std::max(std::abs(r.eps_p1), std::abs(r.eps_p2));
        (r.u_t1 <= 0.8e-3 ? eps_pre : eps_post) =
            std::max(r.u_t1 <= 0.8e-3 ? eps_pre : eps_post, e);
        diff = std::max(diff, std::abs(r.t_t1 - b.rows[k].t_t1));
        peak = std::max(peak, r.t_t1);
    }
    const InterfaceRow& last = a.rows.back();
    const double sample_eps = last.u_n / novel.height;
    std::printf("[ measured ] kappa 1: max |eps_p| %.2e before 0.8 mm, %.2e after; max |novel - "
                "Stutz| t_t1 %.3e kPa; peak %.3f kPa; at 4 mm eps_N %.3e, sample eps_11 %.3e\n",
                eps_pre, eps_post, diff, peak, last.eps_n, sample_eps);
    EXPECT_LT(eps_pre, 1.0e-5);
    EXPECT_LT(eps_post, 1.0e-3);
    EXPECT_LT(diff, 0.5);
    // Softening after the peak, and the two parts no longer deform alike.
    EXPECT_LT(last.t_t1, peak - 1.0);
    EXPECT_GT(std::abs(last.eps_n - sample_eps), 5.0e-3);
}

// Appendix B for the Stutz formulation and for Sanisand as interface model (measured outer
// iterations over 20 steps, perturbation against analytical: hypoplasticity Stutz 38 / 286;
// Sanisand novel 19 / 210, Stutz 27 / 74).
TEST(InterfaceTestAppendixB, PerturbationBeatsAnalyticalForStutzAndSanisand) {
    auto count = [](InterfaceTestSpec spec, ContactJacobian j) {
        spec.contact.jacobian = j;
        spec.stages = {{20, 1.0e-3, 0.0}};
        const DriverRun r = run_driver(spec);
        return r.result.ok ? r.result.counters.newton_iterations : 1000000L;
    };
    InterfaceTestSpec hypo_stutz = l4c_spec(InterfaceFormulation::stutz);
    hypo_stutz.contact.interface.max_subincrement = 4.0e-4;
    std::vector<InterfaceTestSpec> specs = {hypo_stutz};
    for (const auto f : {InterfaceFormulation::novel, InterfaceFormulation::stutz}) {
        InterfaceTestSpec s;
        s.interface_material = karlsruhe_sanisand(0.9);
        s.interface_state = as_vector(sanisand_state());
        s.sample_material = karlsruhe_sanisand(1.0);
        s.sample_state = as_vector(sanisand_state());
        s.contact.interface.formulation = f;
        s.contact.interface.max_subincrement = 1.0e-4;
        specs.push_back(s);
    }
    for (std::size_t i = 0; i < specs.size(); ++i) {
        const long p = count(specs[i], ContactJacobian::perturbation);
        const long a = count(specs[i], ContactJacobian::analytical);
        std::printf("[ measured ] case %zu: Eq. 37 %ld, Eq. B3 %ld outer iterations\n", i, p, a);
        EXPECT_LE(p, 40) << i;
        EXPECT_LT(p, a) << i;
    }
}

// Cyclic CNS shearing (§5.2: t_N0 = -300 kPa, K = 400 kPa/mm, amplitude 0.75 mm), two cycles in
// 30 steps per quarter: t_N = t_N0 - K u_n in every row, the sand compacts cycle by cycle so the
// normal stress relaxes, and the shear stress of the second cycle is lower than the first.
TEST(InterfaceTestCyclic, ConstantNormalStiffnessCycles) {
    for (const auto f : {InterfaceFormulation::novel, InterfaceFormulation::stutz}) {
        InterfaceTestSpec spec = l4c_spec(f, 0.9, -300.0);
        spec.control = NormalControl::constant_stiffness;
        spec.normal_stiffness = 4.0e5;
        spec.contact.interface.max_subincrement = 5.0e-5;
        for (int c = 0; c < 2; ++c) {
            spec.stages.push_back({30, 0.75e-3, 0.0});
            spec.stages.push_back({60, -1.5e-3, 0.0});
            spec.stages.push_back({30, 0.75e-3, 0.0});
        }
        const DriverRun r = run_driver(spec);
        ASSERT_TRUE(r.result.ok) << r.result.reason;
        double peak1 = 0.0, peak2 = 0.0;
        for (const auto& row : r.rows) {
            const double t_N = -300.0 - 4.0e5 * row.u_n;
            EXPECT_NEAR(row.t_n, t_N, spec.newton_tolerance * std::abs(t_N)) << row.step;
            (row.stage <= 3 ? peak1 : peak2) =
                std::max(row.stage <= 3 ? peak1 : peak2, std::abs(row.t_t1));
        }
        expect_shear_strain_follows_slip(r.rows);
        const InterfaceRow& mid = r.rows[120];
        const InterfaceRow& last = r.rows.back();
        std::printf("[ measured ] form %d: u_n after cycle 1 %.3e m, after 2 %.3e m; t_N %.2f, "
                    "%.2f kPa; peak |t_t1| %.2f, %.2f kPa; step cuts %ld\n",
                    static_cast<int>(f), mid.u_n, last.u_n, mid.t_n, last.t_n, peak1, peak2,
                    r.result.counters.step_cuts);
        EXPECT_LT(last.u_n, mid.u_n);
        EXPECT_LT(mid.u_n, 0.0);
        EXPECT_GT(last.t_n, mid.t_n);
        EXPECT_LT(peak2, peak1);
    }
}
