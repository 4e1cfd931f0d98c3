// The sparse solve: UMFPACK and KLU against a dense solve, singular matrices reported, the
// symbolic analysis computed once per pattern and reused over increments, iterations and
// stages with the same DOF map, and a failed increment that names where it failed.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "fem/linear_solver.hpp"
#include "tests/fem/fem_test_support.hpp"

using namespace ifsim;
using namespace ifsim::fem;
using namespace ifsim::fem::testing;

namespace {

Eigen::SparseMatrix<double> small_matrix() {
    Eigen::MatrixXd d(4, 4);
    d << 4, -1, 0, 0.5, -1, 4, -1, 0, 0, -2, 4, -1, 0.5, 0, -1, 3;
    Eigen::SparseMatrix<double> A = d.sparseView();
    A.makeCompressed();
    return A;
}

Stage plate_stage(int steps) {
    Stage st;
    st.steps = steps;
    st.displacements = {{"left", 0, 0.0}, {"right", 0, 0.0}, {"bottom", 1, 0.0}};
    st.equal_displacements = {{"top", 1}};
    st.pressures = {{"top", 50.0, 120.0}};
    return st;
}

StaticSolver hypo_block(LinearSolverKind kind) {
    Mesh m = rectangle_mesh({1.0, 1.0, 3, 3});
    auto mat = material(karlsruhe(), hypo_state({-50, -50, -50, 0, 0, 0}, 0.7));
    SolverSettings s;
    s.linear_solver = kind;
    return StaticSolver(m, {mat}, s);
}

} // namespace

TEST(LinearSolver, UmfpackAndKluSolveLikeADenseLU) {
    const auto A = small_matrix();
    const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(4, 1.0, 4.0);
    const Eigen::VectorXd ref = Eigen::MatrixXd(A).lu().solve(b);
    for (auto kind : {LinearSolverKind::umfpack, LinearSolverKind::klu}) {
        LinearSolver solver(kind);
        std::string err;
        ASSERT_TRUE(solver.factorise(A, 1, err)) << err;
        Eigen::VectorXd x(4);
        ASSERT_TRUE(solver.solve(b.data(), x.data(), err)) << err;
        EXPECT_LT((x - ref).norm(), 1e-13);
        // New values, same pattern: the analysis is reused.
        Eigen::SparseMatrix<double> A2 = A * 2.0;
        ASSERT_TRUE(solver.factorise(A2, 1, err)) << err;
        ASSERT_TRUE(solver.solve(b.data(), x.data(), err)) << err;
        EXPECT_LT((x - 0.5 * ref).norm(), 1e-13);
        EXPECT_EQ(solver.counters().symbolic_analyses, 1);
        EXPECT_EQ(solver.counters().numeric_factorisations, 2);
        ASSERT_TRUE(solver.factorise(A2, 2, err)) << err; // another pattern id: analyse again
        EXPECT_EQ(solver.counters().symbolic_analyses, 2);
    }
}

TEST(LinearSolver, SingularMatrixIsReported) {
    Eigen::MatrixXd d(3, 3);
    d << 1, 1, 0, 1, 1, 0, 0, 0, 2;
    Eigen::SparseMatrix<double> A = d.sparseView();
    A.makeCompressed();
    for (auto kind : {LinearSolverKind::umfpack, LinearSolverKind::klu}) {
        LinearSolver solver(kind);
        std::string err;
        EXPECT_FALSE(solver.factorise(A, 1, err));
        EXPECT_NE(err.find("singular"), std::string::npos) << err;
    }
}

TEST(LinearSolver, SymbolicAnalysisIsReusedWhileThePatternHolds) {
    auto solver = hypo_block(LinearSolverKind::umfpack);
    ASSERT_TRUE(solver.run_stage(plate_stage(3)).ok);
    const auto& c = solver.counters();
    EXPECT_GT(c.newton_iterations, 3);
    EXPECT_EQ(c.linear.symbolic_analyses, 1);
    // One factorisation and solve per Newton iteration and per tangent predictor.
    EXPECT_EQ(c.linear.numeric_factorisations, c.newton_iterations + c.predictor_solves);
    EXPECT_EQ(c.linear.solves, c.newton_iterations + c.predictor_solves);
    EXPECT_EQ(c.patterns_built, 1);

    Stage same = plate_stage(2); // same constraints, other loads: same pattern
    same.pressures = {{"top", 120.0, 150.0}};
    ASSERT_TRUE(solver.run_stage(same).ok);
    EXPECT_EQ(solver.counters().linear.symbolic_analyses, 1);
    EXPECT_EQ(solver.counters().patterns_built, 1);

    Stage other = same; // the plate released: a new DOF map, a new analysis
    other.equal_displacements.clear();
    other.pressures = {{"top", 150.0, 170.0}};
    ASSERT_TRUE(solver.run_stage(other).ok);
    EXPECT_EQ(solver.counters().linear.symbolic_analyses, 2);
    EXPECT_EQ(solver.counters().patterns_built, 2);
}

TEST(LinearSolver, KluGivesTheSameSolutionAsUmfpack) {
    auto a = hypo_block(LinearSolverKind::umfpack);
    auto b = hypo_block(LinearSolverKind::klu);
    ASSERT_TRUE(a.run_stage(plate_stage(3)).ok);
    ASSERT_TRUE(b.run_stage(plate_stage(3)).ok);
    EXPECT_EQ(b.counters().linear.symbolic_analyses, 1);
    const double scale = max_abs(a.displacement());
    EXPECT_GT(scale, 1e-5);
    for (std::size_t d = 0; d < a.displacement().size(); ++d) {
        EXPECT_NEAR(a.displacement()[d], b.displacement()[d], 1e-8 * scale);
    }
}

TEST(LinearSolver, UnsupportedBlockFailsNamingTheIncrement) {
    Mesh m = rectangle_mesh({1.0, 1.0, 2, 2});
    SolverSettings s;
    s.max_cuts = 2;
    StaticSolver solver(m, {material(LinearElasticParams{1e4, 0.3}, elastic_state())}, s);
    Stage st;
    st.name = "floating";
    st.steps = 4;
    st.pressures = {{"top", 0.0, 10.0}}; // no support at all: rigid-body modes
    const auto res = solver.run_stage(st);
    ASSERT_FALSE(res.ok);
    EXPECT_NE(res.reason.find("stage 1 ('floating'), step 1 of 4"), std::string::npos)
        << res.reason;
    EXPECT_NE(res.reason.find("halving the step 2 times"), std::string::npos) << res.reason;
    EXPECT_NE(res.reason.find("singular"), std::string::npos) << res.reason;
    EXPECT_EQ(solver.counters().cuts, 2);
    EXPECT_EQ(solver.counters().increments, 0);
    std::printf("%s\n", res.reason.c_str());
}
