// A run continued from a snapshot of its committed state (checkpoints) goes on exactly as the
// uninterrupted run: a fresh solver of the same model, restored from the snapshot taken after
// increment k of the shear stage and resumed from that increment's cursor, gives every later
// increment's tractions and the final displacements bit for bit, for the novel, Stutz and
// Coulomb interfaces, in 2D and 3D, also when the snapshot falls inside a cut nominal step
// and with reused factorisations.
#include <cstring>

#include <gtest/gtest.h>

#include "tests/fem/fe_shear_box.hpp"

namespace ifsim::fem::testing {
namespace {

bool bitwise_equal(const std::vector<double>& a, const std::vector<double>& b) {
    return a.size() == b.size() &&
           (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

struct Trace {
    std::vector<double> t_t1, t_n;
    std::vector<int> iterations;
};

void record(const StaticSolver& solver, const IncrementInfo& info, Trace& t) {
    const ContactResultant r = solver.contacts()[0]->resultant();
    t.t_t1.push_back(r.shear[0]);
    t.t_n.push_back(r.t_N);
    t.iterations.push_back(static_cast<int>(info.corrections.size()));
}

void expect_resume_matches(const ShearBoxOptions& o, int k) {
    ShearBox a = build_shear_box(o);
    ASSERT_TRUE(a.solver->run_stage(a.consolidation).ok);
    Trace whole;
    SolverSnapshot snap;
    StageCursor cursor;
    int seen = 0;
    ASSERT_TRUE(a.solver
                    ->run_stage(a.shear,
                                [&](const IncrementInfo& info) {
                                    record(*a.solver, info, whole);
                                    if (++seen == k) {
                                        snap = a.solver->snapshot();
                                        cursor = info.next;
                                    }
                                })
                    .ok);
    ASSERT_GE(seen, k);

    ShearBox b = build_shear_box(o);
    b.solver->restore(b.shear, snap);
    Trace rest;
    ASSERT_TRUE(
        b.solver
            ->resume_stage(b.shear, cursor,
                           [&](const IncrementInfo& info) { record(*b.solver, info, rest); })
            .ok);
    ASSERT_EQ(rest.t_t1.size(), whole.t_t1.size() - static_cast<std::size_t>(k));
    const auto tail = [&](const std::vector<double>& v) {
        return std::vector<double>(v.begin() + k, v.end());
    };
    EXPECT_TRUE(bitwise_equal(rest.t_t1, tail(whole.t_t1)));
    EXPECT_TRUE(bitwise_equal(rest.t_n, tail(whole.t_n)));
    EXPECT_EQ(rest.iterations,
              std::vector<int>(whole.iterations.begin() + k, whole.iterations.end()));
    EXPECT_TRUE(bitwise_equal(b.solver->displacement(), a.solver->displacement()));
}

TEST(Snapshot, ResumedShearBoxMatchesTheUninterruptedRunBitForBit) {
    for (InterfaceFormulation f : {InterfaceFormulation::novel, InterfaceFormulation::stutz,
                                   InterfaceFormulation::coulomb}) {
        SCOPED_TRACE(static_cast<int>(f));
        ShearBoxOptions o;
        o.formulation = f;
        o.steps = 12;
        o.displacement = 1.2e-3;
        expect_resume_matches(o, 5);
    }
    ShearBoxOptions three;
    three.dim = 3;
    three.steps = 8;
    three.displacement = 0.8e-3;
    expect_resume_matches(three, 3);
}

// With reused factorisations (GMRES on the held LU) the resumed run, which holds none, still
// takes the same path: the held factorisation lives within one increment.
TEST(Snapshot, ResumedRunWithReusedFactorisationsMatchesBitForBit) {
    ShearBoxOptions o;
    o.steps = 12;
    o.displacement = 1.2e-3;
    o.reuse_factorisation = true;
    expect_resume_matches(o, 5);
}

// Coarse steps get cut: a snapshot inside a nominal step resumes at its cut size and growth.
TEST(Snapshot, ResumeInsideACutStep) {
    ShearBoxOptions o;
    o.steps = 1;
    o.displacement = 1.0e-3;
    o.max_iterations = 6; // a budget that the whole millimetre in one increment exceeds
    ShearBox probe = build_shear_box(o);
    ASSERT_TRUE(probe.solver->run_stage(probe.consolidation).ok);
    int cut = 0, increments = 0;
    const StageResult r = probe.solver->run_stage(probe.shear, [&](const IncrementInfo& info) {
        ++increments;
        cut += info.cut_depth > 0 && info.next.depth > 0 ? 1 : 0;
    });
    ASSERT_TRUE(r.ok) << r.reason;
    ASSERT_GT(cut, 0) << "the case needs cut increments";
    for (int k = 1; k < increments; k += std::max(1, increments / 4)) {
        SCOPED_TRACE(k);
        expect_resume_matches(o, k);
    }
}

} // namespace
} // namespace ifsim::fem::testing
