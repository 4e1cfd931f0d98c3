// The contact pairs' slip viscosity (ContactPairSpec::slip_viscosity, docs/fem.md "Slip
// viscosity"): a viscous shear traction eta dg_T / dt on a continuum interface, used in every
// increment or only when the solver retries an increment that failed at its finest cut. On the
// §5 shear box: its tangent is consistent, it adds eta times the slip rate to the shear (also
// in cut increments), and kept for retries it leaves a run that needs no retry unchanged bit
// for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "tests/fem/fe_shear_box.hpp"

namespace ifsim::fem::testing {
namespace {

ShearBoxOptions box(double eta, bool always) {
    ShearBoxOptions o;
    o.steps = 10;
    o.displacement = 1.0e-3;
    o.adjust = [eta, always](ContactPairSpec& c) {
        c.slip_viscosity = eta;
        c.slip_viscosity_always = always;
    };
    return o;
}

double median(std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
    return v[v.size() / 2];
}

// A viscous stiffness eta / dt of about a tenth of the band's (G / d_s at 100 kPa): a wrong
// sign or a missing tangent term would put ~10 % into the pair's mismatch, where the Eq. 37
// columns alone stay at 4e-4 (test_tangent_check.cpp).
TEST(SlipViscosity, TangentStaysConsistent) {
    ShearBoxOptions o = box(1.0e6, true);
    o.steps = 5;
    o.displacement = 1.0e-3;
    o.check_tangent = true;
    ShearBox b = build_shear_box(o);
    ASSERT_TRUE(b.solver->run_stage(b.consolidation).ok);
    ASSERT_TRUE(b.solver->run_stage(b.shear).ok);
    std::vector<double> pair;
    for (const TangentCheckRecord& r : b.solver->tangent_checks()) {
        if (r.iteration >= 3 && r.step < 1.0e-8) {
            pair.push_back(r.pairs[0]);
        }
    }
    ASSERT_GE(pair.size(), 5u);
    EXPECT_LT(median(pair), 2.0e-3);
    EXPECT_GT(b.solver->counters().contact_viscous_traction_max, 0.0);
}

// The viscous traction is eta x the slip per step: once the band slides, the slip per step
// is the plate's travel per step. It drags the soil along (the shear grows by at least that
// much: the soil then shears more, the band slips less and softens less past its peak).
TEST(SlipViscosity, AddsEtaTimesTheSlipPerStep) {
    const double eta = 2.0e4; // kPa per (m per step): 2 kPa at 1e-4 m per step
    const ShearBoxRun plain = run_shear_box(box(0.0, true));
    const ShearBoxRun viscous = run_shear_box(box(eta, true));
    ASSERT_TRUE(plain.ok) << plain.reason;
    ASSERT_TRUE(viscous.ok) << viscous.reason;
    ASSERT_EQ(plain.t_t1.size(), viscous.t_t1.size());
    const std::size_t n = plain.t_t1.size();
    const double expected = eta * 1.0e-3 / 10.0;
    // The soil element's shear still changes a little from step to step: 1 %.
    EXPECT_NEAR(viscous.counters.contact_viscous_traction_max, expected, 0.01 * expected);
    // t_t1: the shear on the soil along +x, the plate's direction of travel.
    EXPECT_GT(viscous.t_t1[n - 1] - plain.t_t1[n - 1], 0.9 * expected);
    EXPECT_EQ(viscous.counters.viscous_increments, 0); // "always": no retries
    EXPECT_GT(viscous.counters.contact_viscous_point_updates, 0.0);
    // Plain: no viscous counters.
    EXPECT_EQ(plain.counters.contact_viscous_traction_max, 0.0);
}

// In a cut increment the slip and the time share both shrink: at steady sliding the viscous
// traction stays eta x the slip per nominal step. One step of 1 mm with 5 Newton iterations
// needs cuts.
TEST(SlipViscosity, CutIncrementsKeepTheSlipRate) {
    const double eta = 2.0e3; // 2 kPa at 1 mm per step
    ShearBoxOptions o = box(eta, true);
    o.steps = 1;
    o.displacement = 1.0e-3;
    o.max_iterations = 5; // a Newton budget the whole step does not meet: it is cut
    const ShearBoxRun run = run_shear_box(o);
    ASSERT_TRUE(run.ok) << run.reason;
    ASSERT_GT(run.counters.cuts, 0);
    const double expected = eta * 1.0e-3;
    EXPECT_NEAR(run.counters.contact_viscous_traction_max, expected, 0.05 * expected);
}

// Kept for retries, the viscosity acts only where an increment failed at the finest cut.
TEST(SlipViscosity, KeptForRetriesLeavesAConvergingRunUnchanged) {
    const ShearBoxRun plain = run_shear_box(box(0.0, false));
    const ShearBoxRun kept = run_shear_box(box(2.0e4, false));
    ASSERT_TRUE(plain.ok) << plain.reason;
    ASSERT_TRUE(kept.ok) << kept.reason;
    ASSERT_EQ(plain.u.size(), kept.u.size());
    for (std::size_t i = 0; i < plain.u.size(); ++i) {
        EXPECT_EQ(plain.u[i], kept.u[i]) << i;
    }
    EXPECT_EQ(kept.counters.viscous_increments, 0);
    EXPECT_EQ(kept.counters.contact_viscous_point_updates, 0.0);
}

// An increment that fails at the finest cut (here: two Newton iterations, no cut allowed) is
// tried once more with the viscosity, and the run says so when that fails too; a pair without
// a viscosity kept for retries is not retried.
TEST(SlipViscosity, RetriesAnIncrementThatFailedAtTheFinestCut) {
    const auto strict = [](double eta) {
        ShearBoxOptions o = box(eta, false);
        o.steps = 2;
        o.max_iterations = 2;
        o.max_cuts = 0;
        return o;
    };
    const ShearBoxRun plain = run_shear_box(strict(0.0));
    ASSERT_FALSE(plain.ok);
    EXPECT_EQ(plain.reason.find("slip viscosity"), std::string::npos) << plain.reason;
    const ShearBoxRun run = run_shear_box(strict(1.0e6));
    ASSERT_FALSE(run.ok);
    EXPECT_NE(run.reason.find("the last time with the slip viscosity"), std::string::npos)
        << run.reason;
    // The retry's residuals differ from the plain attempt's: the viscous traction acted.
    const std::string suffix = ", the last time with the slip viscosity)";
    std::string retried_reason = run.reason;
    retried_reason.replace(retried_reason.find(suffix), suffix.size(), ")");
    EXPECT_NE(retried_reason, plain.reason);
    EXPECT_EQ(run.counters.viscous_increments, 0);
    // Consolidation needs the same iterations in both; the failed shear increment twice the
    // plain run's two.
    EXPECT_EQ(run.counters.newton_iterations - plain.counters.newton_iterations, 2);
}

} // namespace
} // namespace ifsim::fem::testing
