// Newton systems solved by GMRES with an older factorisation as the preconditioner: GMRES
// against dense solves (no preconditioner, an exact one, restarts, a failing one), the held
// UMFPACK/KLU factorisation preconditioning a changed matrix, a fallback when it cannot, and
// a hypoplastic FE run that reaches the same state with far fewer factorisations.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include <Eigen/Dense>

#include "fem/krylov_gmres.hpp"
#include "fem/linear_solver.hpp"
#include "tests/fem/fem_test_support.hpp"

using namespace ifsim;
using namespace ifsim::fem;
using namespace ifsim::fem::testing;

namespace {

// A non-symmetric, diagonally dominant 1D convection-diffusion matrix.
Eigen::SparseMatrix<double> convection_diffusion(int n, double convection, double shift = 0.0) {
    Eigen::SparseMatrix<double> A(n, n);
    std::vector<Eigen::Triplet<double>> t;
    for (int i = 0; i < n; ++i) {
        t.emplace_back(i, i, 2.0 + shift + 0.01 * i);
        if (i > 0) {
            t.emplace_back(i, i - 1, -1.0 - convection);
        }
        if (i + 1 < n) {
            t.emplace_back(i, i + 1, -1.0 + convection);
        }
    }
    A.setFromTriplets(t.begin(), t.end());
    A.makeCompressed();
    return A;
}

} // namespace

TEST(Gmres, UnpreconditionedReachesTheDenseSolution) {
    const auto A = convection_diffusion(40, 0.3, 0.5);
    const Eigen::MatrixXd D(A);
    const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(40, -1.0, 2.0);
    const Eigen::VectorXd ref = D.lu().solve(b);
    auto apply_a = [&](const auto& v, Eigen::VectorXd& y) { y = D * Eigen::VectorXd(v); };
    auto identity = [](const auto& v, Eigen::VectorXd& z) {
        z = v;
        return true;
    };
    for (const int restart : {40, 7}) { // full GMRES and restarted cycles
        Eigen::VectorXd x = Eigen::VectorXd::Zero(40);
        const auto o = gmres(apply_a, identity, b, x, 1e-12, 400, restart);
        ASSERT_TRUE(o.converged) << restart << " " << o.relative_residual;
        EXPECT_LE(o.relative_residual, 1e-12);
        EXPECT_LT((x - ref).norm(), 1e-9 * ref.norm()) << restart;
        if (restart == 40) { // full GMRES ends within n steps
            EXPECT_LE(o.iterations, 40);
        }
    }
}

TEST(Gmres, ExactPreconditionerTakesOneStepAndFailureStopsIt) {
    const auto A = convection_diffusion(30, 0.4);
    const Eigen::MatrixXd D(A);
    const auto lu = D.lu();
    const Eigen::VectorXd b = Eigen::VectorXd::Ones(30);
    auto apply_a = [&](const auto& v, Eigen::VectorXd& y) { y = D * Eigen::VectorXd(v); };
    auto exact = [&](const auto& v, Eigen::VectorXd& z) {
        z = lu.solve(Eigen::VectorXd(v));
        return true;
    };
    Eigen::VectorXd x = Eigen::VectorXd::Zero(30);
    const auto o = gmres(apply_a, exact, b, x, 1e-12, 20, 20);
    EXPECT_TRUE(o.converged);
    EXPECT_EQ(o.iterations, 1);
    EXPECT_LT((D * x - b).norm(), 1e-12 * b.norm());
    auto failing = [](const auto&, Eigen::VectorXd&) { return false; };
    Eigen::VectorXd y = Eigen::VectorXd::Zero(30);
    EXPECT_FALSE(gmres(apply_a, failing, b, y, 1e-12, 20, 20).converged);
}

// The factorisation of A0 preconditions A1 = A0 with changed values: GMRES reaches A1's
// solution in a few steps; with a budget too small it reports a fallback.
TEST(ReusedFactorisation, HeldLuPreconditionsAChangedMatrix) {
    const int n = 200;
    const auto A0 = convection_diffusion(n, 0.3);
    auto A1 = convection_diffusion(n, 0.33, 0.05); // the same pattern, new values
    const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, 1.0, -1.0);
    const Eigen::VectorXd ref = Eigen::MatrixXd(A1).lu().solve(b);
    for (auto kind : {LinearSolverKind::umfpack, LinearSolverKind::klu}) {
        LinearSolver solver(kind);
        std::string err;
        EXPECT_FALSE(solver.holds_factorisation(1));
        ASSERT_TRUE(solver.factorise(A0, 1, err)) << err;
        EXPECT_TRUE(solver.holds_factorisation(1));
        EXPECT_FALSE(solver.holds_factorisation(2)); // another pattern
        Eigen::VectorXd x(n);
        ASSERT_TRUE(solver.solve_preconditioned(A1, b.data(), x.data(), 1e-12, 30));
        EXPECT_LT((x - ref).norm(), 1e-9 * ref.norm());
        const auto& c = solver.counters();
        EXPECT_EQ(c.numeric_factorisations, 1);
        EXPECT_EQ(c.krylov_solves, 1);
        EXPECT_GE(c.krylov_iterations, 2); // A1 differs: more than one step
        EXPECT_LE(c.krylov_iterations, 15);
        EXPECT_EQ(c.krylov_fallbacks, 0);
        // One step is not enough for 1e-12: not converged, counted, x left to the caller.
        EXPECT_FALSE(solver.solve_preconditioned(A1, b.data(), x.data(), 1e-12, 1));
        EXPECT_EQ(solver.counters().krylov_fallbacks, 1);
    }
}

// The preconditioner's factors in single precision are the factorised matrix's inverse to
// rounding: GMRES on that same matrix converges to 1e-12 in at most three steps (one in double,
// where the copied factors are its inverse to double rounding).
TEST(ReusedFactorisation, SinglePrecisionFactorsAreTheInverseToRounding) {
    const int n = 200;
    const auto A = convection_diffusion(n, 0.3);
    const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, 1.0, -1.0);
    const Eigen::VectorXd ref = Eigen::MatrixXd(A).lu().solve(b);
    for (auto precision : {LuPrecision::double_precision, LuPrecision::single_precision}) {
        LinearSolver solver(LinearSolverKind::umfpack, precision);
        std::string err;
        ASSERT_TRUE(solver.factorise(A, 1, err)) << err;
        Eigen::VectorXd x(n);
        ASSERT_TRUE(solver.solve_preconditioned(A, b.data(), x.data(), 1e-12, 30));
        EXPECT_LT((x - ref).norm(), 1e-10 * ref.norm());
        const long steps = solver.counters().krylov_iterations;
        if (precision == LuPrecision::double_precision) {
            EXPECT_EQ(steps, 1);
        } else {
            EXPECT_GE(steps, 2); // one step leaves single precision's rounding
            EXPECT_LE(steps, 3);
        }
    }
}

namespace {

// A hypoplastic block loaded by a plate from 50 to 120 kPa in 8 steps.
StageRun plate_run(bool reuse,
                   double factorisation_cost = SolverSettings{}.krylov_factorisation_cost,
                   LuPrecision precision = SolverSettings{}.preconditioner_precision) {
    Mesh m = rectangle_mesh({1.0, 1.0, 6, 6});
    distort(m, 0.1, 1.0 / 6.0);
    SolverSettings s;
    s.reuse_factorisation = reuse;
    s.krylov_factorisation_cost = factorisation_cost;
    s.preconditioner_precision = precision;
    Stage st;
    st.steps = 8;
    st.displacements = {{"left", 0, 0.0}, {"right", 0, 0.0}, {"bottom", 1, 0.0}};
    st.equal_displacements = {{"top", 1}};
    st.pressures = {{"top", 50.0, 120.0}};
    return run_hypoplastic_stage(m, hypo_state({-50, -50, -50, 0, 0, 0}, 0.7), s, st);
}

} // namespace

// The same converged state (to the Newton tolerance) with far fewer factorisations, with the
// preconditioner's factors in double and in single precision.
TEST(ReusedFactorisation, HypoplasticRunReachesTheSameStateWithFewerFactorisations) {
    const StageRun direct = plate_run(false);
    const StageRun single =
        plate_run(true, SolverSettings{}.krylov_factorisation_cost, LuPrecision::single_precision);
    ASSERT_TRUE(single.result.ok) << single.result.reason;
    EXPECT_GT(single.counters.linear.krylov_solves, 0);
    for (int i = 0; i < 6; ++i) {
        EXPECT_NEAR(single.stress[i], direct.stress[i], 1e-7 * std::abs(direct.stress[1])) << i;
    }
    const StageRun reused =
        plate_run(true, SolverSettings{}.krylov_factorisation_cost, LuPrecision::double_precision);
    ASSERT_TRUE(direct.result.ok) << direct.result.reason;
    ASSERT_TRUE(reused.result.ok) << reused.result.reason;
    const auto& d = direct.counters.linear;
    const auto& r = reused.counters.linear;
    std::printf("direct: %ld iterations, %ld factorisations; reused: %ld iterations, %ld "
                "factorisations, %ld Krylov solves (%ld steps, %ld fallbacks)\n",
                direct.counters.newton_iterations, d.numeric_factorisations,
                reused.counters.newton_iterations, r.numeric_factorisations, r.krylov_solves,
                r.krylov_iterations, r.krylov_fallbacks);
    EXPECT_EQ(d.krylov_solves, 0);
    EXPECT_GT(r.krylov_solves, 0);
    EXPECT_LT(r.numeric_factorisations * 2, d.numeric_factorisations);
    // Exact-enough linear solves keep Newton's iteration count.
    EXPECT_LE(reused.counters.newton_iterations, direct.counters.newton_iterations + 2);
    for (int i = 0; i < 6; ++i) {
        EXPECT_NEAR(reused.stress[i], direct.stress[i], 1e-7 * std::abs(direct.stress[1])) << i;
    }
}

// The keep-or-refactorise rule: a factorisation priced at nothing is replaced after every
// Krylov solve that needed a step; one priced beyond reach is kept for the whole increment
// (a new one only at each increment start, or when GMRES fails). Both reach the direct state.
TEST(ReusedFactorisation, FactorisationCostDecidesWhenTheHeldOneIsReplaced) {
    const StageRun direct = plate_run(false);
    const StageRun free_lu = plate_run(true, 0.0);
    const StageRun dear_lu = plate_run(true, 1.0e6);
    ASSERT_TRUE(free_lu.result.ok) << free_lu.result.reason;
    ASSERT_TRUE(dear_lu.result.ok) << dear_lu.result.reason;
    const auto& f = free_lu.counters.linear;
    const auto& d = dear_lu.counters.linear;
    EXPECT_EQ(d.numeric_factorisations,
              dear_lu.counters.increments + dear_lu.counters.cuts + d.krylov_fallbacks);
    EXPECT_GT(f.numeric_factorisations, d.numeric_factorisations);
    // Priced at nothing, no two Krylov solves in a row: at least every other solve factorises.
    EXPECT_GE(2 * f.numeric_factorisations + 1, f.solves);
    for (const StageRun* r : {&free_lu, &dear_lu}) {
        for (int i = 0; i < 6; ++i) {
            EXPECT_NEAR(r->stress[i], direct.stress[i], 1e-7 * std::abs(direct.stress[1])) << i;
        }
    }
}
