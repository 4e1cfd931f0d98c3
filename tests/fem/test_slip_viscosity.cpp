// The contact pairs' slip viscosity (ContactPairSpec::slip_viscosity, docs/fem.md "Slip
// viscosity"): a viscous shear traction eta dg_T / dt on a continuum interface, used in every
// increment or only when the solver retries an increment that failed at its finest cut. On the
// §5 shear box: its tangent is consistent, it adds eta times the slip rate to the shear (also
// in cut increments), and kept for retries it leaves a run that needs no retry unchanged bit
// for bit. Pushed by force past the band's capacity, a run that holds the viscosity at the
// finest cut (SolverSettings::hold_slip_viscosity) ends where the retrying run ends, with fewer
// failed attempts, also when resumed from a snapshot.
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

// Force control past the band's capacity: the plate is fixed and a pressure on the soil's left
// face pushes the soil along +x (shear on the band = pressure x 0.02 m / 0.1 m). The soil is
// elastic, so only the band can fail. A preload stage takes the band to 38 kPa of shear; the push
// stage ramps it to 48 kPa in two steps, past the band's limit (about 41 kPa: with the
// viscosity's 1e5 kPa per m of slip per step the slip grows without bound beyond it). There no
// static equilibrium exists: at the finest cut every increment fails without the viscosity.
struct PushBox {
    ShearBox box;
    Stage preload, push;
};

PushBox push_past_capacity(bool hold) {
    ShearBoxOptions o = box(1.0e5, false);
    o.elastic_soil = true;
    o.max_cuts = 2;
    o.max_iterations = 4; // a failed attempt costs 4 iterations (no divergence before)
    o.hold_slip_viscosity = hold;
    PushBox p{build_shear_box(o), {}, {}};
    Stage push = p.box.consolidation;
    push.name = "push";
    push.steps = 2;
    // The soil's top is free along x (tied, as a rigid cap); the plate stays fixed.
    std::erase_if(push.displacements,
                  [](const PrescribedDisplacement& d) { return d.node_set == "soil.top"; });
    push.equal_displacements.push_back({"soil.top", 0});
    p.preload = push;
    p.preload.name = "preload";
    p.preload.steps = 1;
    p.preload.pressures.push_back({"soil.left", 0.0, 190.0});
    p.push = push;
    p.push.pressures.push_back({"soil.left", 190.0, 240.0});
    return p;
}

struct PushRun {
    StageResult result;
    std::vector<double> u;
    SolverCounters counters;
    // After the first increment whose successor takes the viscosity at once (held runs):
    SolverSnapshot snapshot;
    StageCursor cursor;
    long holds_before = 0;          // held increments committed before the snapshot
    long iterations_before = 0;     // Newton iterations before the snapshot
    int misplaced_holds = 0;        // held increments not at the finest cut or first in their step
    std::vector<double> t_t1_after; // band shear after each later increment
};

PushRun run_push(PushBox& p) {
    StaticSolver& solver = *p.box.solver;
    PushRun r;
    r.result = solver.run_stage(p.box.consolidation);
    if (r.result.ok) {
        r.result = solver.run_stage(p.preload);
    }
    if (r.result.ok) {
        bool taken = false;
        long holds = solver.counters().viscous_holds;
        r.result = solver.run_stage(p.push, [&](const IncrementInfo& info) {
            if (solver.counters().viscous_holds > holds) {
                holds = solver.counters().viscous_holds;
                const bool first_of_step = info.t_begin == double(info.step - 1) / p.push.steps;
                r.misplaced_holds += info.cut_depth != 2 || first_of_step ? 1 : 0;
            }
            if (taken) {
                r.t_t1_after.push_back(solver.contacts()[0]->resultant().shear[0]);
            }
            if (!taken && info.next.viscous_held) {
                taken = true;
                r.snapshot = solver.snapshot();
                r.cursor = info.next;
                r.holds_before = solver.counters().viscous_holds;
                r.iterations_before = solver.counters().newton_iterations;
            }
        });
    }
    r.u = solver.displacement();
    r.counters = solver.counters();
    return r;
}

// Held (SolverSettings::hold_slip_viscosity): the increments after the first viscous one at the
// finest cut take the viscosity at once. The held solve is the retry's (same state, same first
// guess), so the run ends bitwise where the retrying run ends, with one failed attempt (the
// Newton budget, 4 iterations) fewer per held increment.
TEST(SlipViscosity, HeldViscositySkipsTheFailedFirstAttemptsAndKeepsTheResult) {
    PushBox a = push_past_capacity(false);
    PushBox b = push_past_capacity(true);
    const PushRun retried = run_push(a);
    const PushRun held = run_push(b);
    ASSERT_TRUE(retried.result.ok) << retried.result.reason;
    ASSERT_TRUE(held.result.ok) << held.result.reason;
    ASSERT_GE(retried.counters.viscous_increments, 2);
    EXPECT_EQ(retried.counters.viscous_holds, 0);
    EXPECT_EQ(held.counters.viscous_increments, retried.counters.viscous_increments);
    ASSERT_GE(held.counters.viscous_holds, 2);
    EXPECT_LT(held.counters.viscous_holds, held.counters.viscous_increments);
    EXPECT_EQ(retried.counters.newton_iterations - held.counters.newton_iterations,
              4 * held.counters.viscous_holds);
    EXPECT_EQ(held.counters.cuts, retried.counters.cuts);
    EXPECT_EQ(held.misplaced_holds, 0); // a hold never leaks into a grown increment or step
    ASSERT_EQ(held.u.size(), retried.u.size());
    for (std::size_t i = 0; i < held.u.size(); ++i) {
        EXPECT_EQ(held.u[i], retried.u[i]) << i;
    }
}

// A run resumed from a snapshot taken where the next increment is held goes on holding: the
// stage cursor carries the flag (and checkpoints write it), so the rest is bit for bit the same,
// with as many held increments (dropped, the first would fail once more without the viscosity).
TEST(SlipViscosity, ResumedRunKeepsTheHeldViscosity) {
    PushBox a = push_past_capacity(true);
    const PushRun whole = run_push(a);
    ASSERT_TRUE(whole.result.ok) << whole.result.reason;
    ASSERT_TRUE(whole.cursor.viscous_held);
    ASSERT_FALSE(whole.t_t1_after.empty());

    PushBox b = push_past_capacity(true);
    StaticSolver& solver = *b.box.solver;
    ASSERT_TRUE(solver.run_stage(b.box.consolidation).ok);
    ASSERT_TRUE(solver.run_stage(b.preload).ok);
    solver.restore(b.push, whole.snapshot);
    const SolverCounters before = solver.counters();
    std::vector<double> t_t1;
    const StageResult r = solver.resume_stage(b.push, whole.cursor, [&](const IncrementInfo&) {
        t_t1.push_back(solver.contacts()[0]->resultant().shear[0]);
    });
    ASSERT_TRUE(r.ok) << r.reason;
    EXPECT_EQ(t_t1, whole.t_t1_after);
    EXPECT_EQ(solver.displacement(), whole.u);
    EXPECT_EQ(solver.counters().viscous_holds - before.viscous_holds,
              whole.counters.viscous_holds - whole.holds_before);
    EXPECT_EQ(solver.counters().newton_iterations - before.newton_iterations,
              whole.counters.newton_iterations - whole.iterations_before);
}

} // namespace
} // namespace ifsim::fem::testing
