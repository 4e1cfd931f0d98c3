// The finite-element shear box with the hypoplastic interface wired into the static solver
// (mortar contact, Eqs. 14-16 gathered per increment, Eq. 37 Jacobian columns in the global
// tangent) against the point-level interface test of the same sample, and the properties the
// solver must keep: CNL, the Jacobian schemes' iteration counts, 2D = 3D for a uniform box,
// one thread = two threads bitwise.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#define IFSIM_TEST_ENGINE_HELPERS
#include "tests/fem/fe_shear_box.hpp"

using namespace ifsim;
using namespace ifsim::fem;
using namespace ifsim::fem::testing;

namespace {

// The point-level twin: same sample (height 0.02 m), same interface, same plate travel.
test::DriverRun point_level(const ShearBoxOptions& o) {
    InterfaceTestSpec spec = test::l4c_spec(o.formulation);
    spec.sample_state[6] = 0.81;
    spec.interface_state[6] = 0.81;
    spec.contact.interface.max_subincrement = o.max_subincrement;
    spec.contact.interface.ndim = o.dim; // 2: plane strain, eps_p2 = 0 (sigma_p2 not imposed)
    spec.stages = {{o.steps, o.displacement, 0.0}};
    return test::run_driver(spec);
}

double interpolate(const std::vector<double>& x, const std::vector<double>& y, double at) {
    for (std::size_t k = 1; k < x.size(); ++k) {
        if (x[k] >= at) {
            const double w = (at - x[k - 1]) / (x[k] - x[k - 1]);
            return y[k - 1] + w * (y[k] - y[k - 1]);
        }
    }
    return y.back();
}

// Largest difference of the FE box's mean shear traction from the point-level test's at the
// same plate travel; prints both at the end.
double worst_difference(const ShearBoxOptions& o, const ShearBoxRun& fe) {
    const auto pt = point_level(o);
    EXPECT_TRUE(pt.result.ok) << pt.result.reason;
    std::vector<double> u_pt, tau_pt;
    for (const auto& row : pt.rows) {
        u_pt.push_back(row.u_t1);
        tau_pt.push_back(row.t_t1);
    }
    double worst = 0.0;
    for (std::size_t k = 0; k < fe.u_t1.size(); ++k) {
        worst = std::max(worst, std::abs(fe.t_t1[k] - interpolate(u_pt, tau_pt, fe.u_t1[k])));
    }
    std::printf("%dD, %d increments: FE tau %.3f kPa, point level %.3f kPa at %.2g mm; worst "
                "difference %.3f kPa\n",
                o.dim, o.steps, fe.t_t1.back(), tau_pt.back(), 1e3 * fe.u_t1.back(), worst);
    return worst;
}

// The FE box adds to the point-level idealisation only the penalty's compliance and the
// explicit gather of s_p1, s_p2 (the continuum stress of the last converged increment, as the
// paper gathers per increment): the curves agree within a small fraction of the shear stress.
// The 2D box is compared with the point-level test in plane strain (eps_p2 = 0).
TEST(FeShearBox, FollowsThePointLevelTestUnderConstantNormalLoadIn2DAnd3D) {
    for (int dim : {2, 3}) {
        ShearBoxOptions o;
        o.dim = dim;
        o.steps = 40;
        const ShearBoxRun fe = run_shear_box(o);
        ASSERT_TRUE(fe.ok) << fe.reason;
        for (std::size_t k = 0; k < fe.u_t1.size(); ++k) {
            EXPECT_NEAR(fe.t_n[k], -100.0, 1.0e-3 * 100.0) << "CNL, increment " << k;
        }
        EXPECT_GT(fe.t_t1.back(), 40.0); // the interface carries shear
        EXPECT_LT(worst_difference(o, fe), 0.02 * fe.t_t1.back()) << dim << "D";
    }
}

// The lag of the explicit gather is O(increment): the difference shrinks with the increments.
// The explicit gather (the paper's: in-plane targets from the last converged increment) lags
// by O(increment); the implicit gather (default) removes the lag, so even 10 increments agree
// with the point-level test to 0.2 % of tau.
TEST(FeShearBox, DifferenceToThePointLevelTestShrinksWithTheIncrement) {
    ShearBoxOptions o;
    o.dim = 3;
    o.max_gathers = 0;
    o.steps = 10;
    const double coarse = worst_difference(o, run_shear_box(o));
    o.steps = 40;
    const double fine = worst_difference(o, run_shear_box(o));
    EXPECT_LT(fine, 0.5 * coarse);
    o.max_gathers = SolverSettings{}.max_gathers;
    o.steps = 10;
    const double implicit = worst_difference(o, run_shear_box(o));
    EXPECT_LT(implicit, 0.25 * coarse);
    EXPECT_LT(implicit, 0.12); // kPa, tau about 57 kPa
}

TEST(FeShearBox, Eq37JacobianConvergesInFewerIterationsThanAnalyticalB3) {
    ShearBoxOptions o;
    o.steps = 10;
    o.max_gathers = 0; // one Newton run per increment: its convergence order is the subject
    const ShearBoxRun a = run_shear_box(o);
    o.jacobian = ContactJacobian::analytical;
    const ShearBoxRun b = run_shear_box(o);
    ASSERT_TRUE(a.ok) << a.reason;
    long total_a = 0, total_b = 0;
    for (std::size_t k = 0; k < a.iterations.size(); ++k) {
        total_a += a.iterations[k];
        // The first shear increment starts from rest (no extrapolation yet).
        EXPECT_LE(a.iterations[k], k == 0 ? 10 : 6) << "increment " << k;
    }
    for (int k : b.iterations) {
        total_b += k;
    }
    for (std::size_t k = 0; k < a.residuals.size(); ++k) {
        std::printf("increment %zu:", k);
        for (double r : a.residuals[k]) {
            std::printf(" %.1e", r);
        }
        std::printf("\n");
    }
    // Superlinear in the last iterations: each residual in [1e-10, 1e-3] is followed by one
    // below 10 r^1.3 (B3's linear x0.95 per iteration would not be).
    int checked = 0;
    for (const auto& seq : a.residuals) {
        for (std::size_t k = 0; k + 1 < seq.size(); ++k) {
            if (seq[k] <= 1.0e-3 && seq[k] >= 1.0e-10) {
                EXPECT_LE(seq[k + 1], 10.0 * std::pow(seq[k], 1.3)) << seq[k];
                ++checked;
            }
        }
    }
    EXPECT_GE(checked, 10);
    std::printf("Newton iterations over %d increments: Eq. 37 %ld, Eq. B3 %ld%s\n", o.steps,
                total_a, total_b, b.ok ? "" : " (B3 run failed)");
    EXPECT_LT(total_a, total_b);
}

// A hard case ends in a defined state: when Algorithm 1 cannot meet its tolerance (here: one
// Newton iteration allowed for a tolerance of 1e-12), the solver halves the increment, then
// stops with a reason naming the pair, the point and the cause; nothing non-finite is committed.
TEST(FeShearBox, FailingInterfacePointStopsTheRunWithADiagnostic) {
    ShearBoxOptions o;
    o.steps = 4;
    o.adjust = [](ContactPairSpec& c) {
        c.options.interface.tolerance = 1.0e-12;
        c.options.interface.max_newton_iterations = 1;
        c.options.interface.polish_iterations = 0;
        c.options.interface.newton_fallback = false; // no second try to rescue it
    };
    const ShearBoxRun r = run_shear_box(o);
    ASSERT_FALSE(r.ok);
    EXPECT_NE(r.reason.find("contact pair 'interface'"), std::string::npos) << r.reason;
    EXPECT_NE(r.reason.find("failed in Algorithm 1"), std::string::npos) << r.reason;
    EXPECT_NE(r.reason.find("halving the step"), std::string::npos) << r.reason;
    EXPECT_GT(r.counters.contact_failures, 0);
    std::printf("%s\n", r.reason.c_str());
    ASSERT_FALSE(r.u.empty());
    for (double v : r.u) {
        EXPECT_TRUE(std::isfinite(v));
    }
}

// Any continuum model of the material engine plugs into the FE interface unchanged: Sanisand
// (Karlsruhe sand, kappa = 0.9) as interface model under the hypoplastic soil, 2D and 3D.
TEST(FeShearBox, SanisandInterfaceRunsInTheSameBox) {
    for (int dim : {2, 3}) {
        ShearBoxOptions o;
        o.dim = dim;
        o.steps = 10;
        o.adjust = [](ContactPairSpec& c) {
            c.interface_material = test::karlsruhe_sanisand(0.9);
            c.initial_state = [](const Voigt6& s) {
                return test::as_vector(
                    Sanisand::initial_state({s[0], s[1], s[2], s[3], s[4], s[5]}, 0.75));
            };
        };
        const ShearBoxRun r = run_shear_box(o);
        ASSERT_TRUE(r.ok) << dim << "D: " << r.reason;
        for (std::size_t k = 0; k < r.t_t1.size(); ++k) {
            EXPECT_NEAR(r.t_n[k], -100.0, 0.1) << "CNL, increment " << k;
        }
        EXPECT_GT(r.t_t1.back(), 10.0); // mobilised shear, below the Coulomb-like limit
        EXPECT_LT(r.t_t1.back(), 100.0);
        std::printf("%dD Sanisand interface: tau %.2f kPa at %.2g mm, %ld Newton iterations\n", dim,
                    r.t_t1.back(), 1e3 * r.u_t1.back(), r.counters.newton_iterations);
    }
}

// Deferring the Eq. 37 lanes to the tangent pass changes nothing but the work: the base lanes
// repeat the residual's evaluation bitwise, so displacements and tractions are identical.
TEST(FeShearBox, DeferredJacobianLanesGiveBitwiseEqualResultsWithFewerLanes) {
    for (bool adaptive : {false, true}) {
        ShearBoxOptions o;
        o.steps = 6;
        o.adjust = [adaptive](ContactPairSpec& c) {
            c.options.interface.adaptive = adaptive;
            c.defer_jacobian = false;
        };
        const ShearBoxRun eager = run_shear_box(o);
        o.adjust = [adaptive](ContactPairSpec& c) {
            c.options.interface.adaptive = adaptive;
            c.defer_jacobian = true;
        };
        const ShearBoxRun deferred = run_shear_box(o);
        ASSERT_TRUE(eager.ok && deferred.ok) << eager.reason << deferred.reason;
        ASSERT_EQ(eager.u.size(), deferred.u.size());
        EXPECT_EQ(std::memcmp(eager.u.data(), deferred.u.data(), eager.u.size() * sizeof(double)),
                  0);
        EXPECT_EQ(eager.t_t1, deferred.t_t1);
        EXPECT_EQ(eager.counters.newton_iterations, deferred.counters.newton_iterations);
        EXPECT_LT(deferred.counters.contact_lanes, eager.counters.contact_lanes);
        std::printf("adaptive %d: contact lanes %.0f eager, %.0f deferred\n", adaptive,
                    eager.counters.contact_lanes, deferred.counters.contact_lanes);
    }
}

// Adaptive sub-increments held through each increment's Newton iterations
// (ContactPairSpec::hold_partition, the default) against sub-increments chosen anew in every
// evaluation: the held run does less interface work and stays, like the other, within the
// error control's tolerance of a tight reference (tolerances 1e-5 for Algorithm 1, its error
// control and the model). One thread against two gives the same bits with held sub-increments.
TEST(FeShearBox, HeldSubincrementsCostLessAndStayAsAccurate) {
    ShearBoxOptions o;
    o.steps = 10;
    o.displacement = 2.0e-3;
    auto with = [&](bool hold, double tolerance, int threads) {
        o.threads = threads;
        o.adjust = [hold, tolerance](ContactPairSpec& c) {
            c.options.interface.adaptive = true;
            c.hold_partition = hold;
            if (tolerance > 0.0) {
                c.options.interface.tolerance = tolerance;
                c.options.interface.adaptive_tolerance = tolerance;
                c.options.interface.model.tolerance = tolerance;
            }
        };
        return run_shear_box(o);
    };
    const ShearBoxRun ref = with(false, 1.0e-5, 0);
    const ShearBoxRun held = with(true, 0.0, 1);
    const ShearBoxRun anew = with(false, 0.0, 0);
    ASSERT_TRUE(ref.ok && held.ok && anew.ok) << ref.reason << held.reason << anew.reason;
    ASSERT_EQ(held.t_t1.size(), ref.t_t1.size());
    ASSERT_EQ(anew.t_t1.size(), ref.t_t1.size());
    double err_held = 0.0, err_anew = 0.0, scale = 0.0;
    for (std::size_t k = 0; k < ref.t_t1.size(); ++k) {
        err_held = std::max(err_held, std::abs(held.t_t1[k] - ref.t_t1[k]));
        err_anew = std::max(err_anew, std::abs(anew.t_t1[k] - ref.t_t1[k]));
        scale = std::max(scale, std::abs(ref.t_t1[k]));
    }
    std::printf("shear error against the reference: held %.3g kPa, chosen anew %.3g kPa (of %.3g); "
                "interface model substeps %.0f held, %.0f anew\n",
                err_held, err_anew, scale, held.counters.contact_model_substeps,
                anew.counters.contact_model_substeps);
    // Both within the error control's tolerance (2e-3) of the shear they reach; the held run
    // with fewer model substeps (the interface models' unit of work).
    const double tolerance = InterfaceSettings{}.adaptive_tolerance;
    EXPECT_LE(err_held, tolerance * scale);
    EXPECT_LE(err_anew, tolerance * scale);
    EXPECT_LT(held.counters.contact_model_substeps, anew.counters.contact_model_substeps);
    // The release after convergence is reached (the first shear increments outgrow the slip
    // their counts were chosen for) and only where counts are held.
    EXPECT_GT(held.counters.partition_solves, 0);
    EXPECT_EQ(anew.counters.partition_solves, 0);

    const ShearBoxRun two = with(true, 0.0, 2);
    ASSERT_TRUE(two.ok) << two.reason;
    ASSERT_EQ(held.u.size(), two.u.size());
    EXPECT_EQ(std::memcmp(held.u.data(), two.u.data(), held.u.size() * sizeof(double)), 0);
}

TEST(FeShearBox, OneAndTwoThreadsGiveBitwiseEqualDisplacements) {
    ShearBoxOptions o;
    o.steps = 4;
    o.threads = 1;
    const ShearBoxRun a = run_shear_box(o);
    o.threads = 2;
    const ShearBoxRun b = run_shear_box(o);
    ASSERT_TRUE(a.ok && b.ok);
    ASSERT_EQ(a.u.size(), b.u.size());
    EXPECT_EQ(std::memcmp(a.u.data(), b.u.data(), a.u.size() * sizeof(double)), 0);
    EXPECT_EQ(std::memcmp(a.t_t1.data(), b.t_t1.data(), a.t_t1.size() * sizeof(double)), 0);
}

} // namespace
