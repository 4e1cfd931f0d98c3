// The assembled tangent against central finite differences of the global residual, at a
// non-trivial trial increment of one increment: exact for linear elasticity (with hourglass
// control); for a hypoplastic block with the adaptive perturbation lanes consistent to the
// accuracy of the difference quotients, with the fixed-substep scheme off by an amount set by
// the substep size (see docs/fem.md).
#include <gtest/gtest.h>

#include <cstdio>

#include <Eigen/Dense>

#include "tests/fem/fem_test_support.hpp"

using namespace ifsim;
using namespace ifsim::fem;
using namespace ifsim::fem::testing;

namespace {

struct Mismatch {
    double relative = 0.0; // ||K - K_fd||_F / ||K||_F
    double scale = 0.0;    // ||K||_F
};

// K = -dR/du: central differences of the residual, one equation at a time (a tied equation
// moves all its DOFs together).
Mismatch tangent_mismatch(StaticSolver& solver, const Stage& st, double h) {
    solver.begin_stage(st);
    const DofMap& dm = solver.dof_map();
    const int n = dm.n_equations;
    std::vector<double> du(static_cast<std::size_t>(dm.n_dofs()), 0.0);
    for (std::size_t k = 0; k < dm.prescribed.size(); ++k) {
        du[static_cast<std::size_t>(dm.prescribed[k])] = dm.prescribed_change[k];
    }
    for (int d = 0; d < dm.n_dofs(); ++d) { // a trial state away from the start
        if (dm.equation[static_cast<std::size_t>(d)] >= 0) {
            du[static_cast<std::size_t>(d)] = 2e-4 * std::sin(1.3 * d);
        }
    }
    std::string err;
    EXPECT_TRUE(solver.evaluate(1.0, du, true, err)) << err;
    const Eigen::MatrixXd K = Eigen::MatrixXd(solver.tangent_matrix());
    Eigen::MatrixXd F(n, n);
    for (int j = 0; j < n; ++j) {
        auto up = du;
        auto um = du;
        for (int d = 0; d < dm.n_dofs(); ++d) {
            if (dm.equation[static_cast<std::size_t>(d)] == j) {
                up[static_cast<std::size_t>(d)] += h;
                um[static_cast<std::size_t>(d)] -= h;
            }
        }
        EXPECT_TRUE(solver.evaluate(1.0, up, false, err)) << err;
        const auto rp = solver.residual();
        EXPECT_TRUE(solver.evaluate(1.0, um, false, err)) << err;
        const auto& rm = solver.residual();
        for (int i = 0; i < n; ++i) {
            F(i, j) =
                -(rp[static_cast<std::size_t>(i)] - rm[static_cast<std::size_t>(i)]) / (2.0 * h);
        }
    }
    return {(K - F).norm() / K.norm(), K.norm()};
}

Stage shear_and_compression(int dim) {
    Stage st;
    const int v = dim - 1;
    st.displacements = {
        {"bottom", 0, 0.0}, {"bottom", v, 0.0}, {"top", v, -1e-3}, {"top", 0, 5e-4}};
    if (dim == 3) {
        st.displacements.push_back({"bottom", 1, 0.0});
    }
    st.equal_displacements = {{"right_mid", 0}}; // a tied set: equations span elements
    return st;
}

// The right side without its top and bottom nodes (those are prescribed).
void add_right_mid(Mesh& m) {
    auto& set = m.node_sets["right_mid"];
    for (int n : m.node_set("right")) {
        const double z = m.coordinate(n, m.dim() - 1);
        if (z > 0.25 && z < 0.75) {
            set.push_back(n);
        }
    }
}

StaticSolver hypo_block(int dim, bool igs, double tolerance, bool fixed_substeps = false) {
    Mesh m = dim == 3 ? box_mesh({1.0, 0.5, 1.0, 2, 1, 2}) : rectangle_mesh({1.0, 1.0, 2, 2});
    distort(m, 0.1, 0.5);
    add_right_mid(m);
    auto p = karlsruhe();
    p.intergranular_strain = igs;
    auto mat = material(p, hypo_state({-100, -100, -100, 0, 0, 0}, 0.65));
    mat.k0 = K0Stress{1.0, 16.0, 50.0, 0.5};
    SolverSettings s;
    s.update.settings.tolerance = tolerance;
    s.tangent.fixed_substeps = fixed_substeps;
    return StaticSolver(m, {mat}, s);
}

} // namespace

TEST(Tangent, LinearElasticWithHourglassControlIsExact) {
    Mesh m = box_mesh({1.0, 0.5, 1.0, 2, 1, 2});
    distort(m, 0.1, 0.5);
    add_right_mid(m);
    SolverSettings s;
    s.integration = Integration::reduced;
    StaticSolver solver(m, {material(LinearElasticParams{2e4, 0.3}, elastic_state(10.0))}, s);
    const auto mm = tangent_mismatch(solver, shear_and_compression(3), 1e-6);
    EXPECT_LT(mm.relative, 1e-8);
}

TEST(Tangent, HypoplasticityWithoutIntergranularStrainMatchesFiniteDifferences) {
    auto solver = hypo_block(3, false, 1e-3); // the default integration tolerance
    const auto mm = tangent_mismatch(solver, shear_and_compression(3), 1e-8);
    std::printf("relative mismatch %.3e\n", mm.relative);
    EXPECT_GT(mm.scale, 1e3);
    EXPECT_LT(mm.relative, 1e-6);
    EXPECT_EQ(solver.counters().tangent_fallbacks, 0);
}

TEST(Tangent, HypoplasticityWithIntergranularStrainMatchesFiniteDifferences3D) {
    auto solver = hypo_block(3, true, 1e-3);
    const auto mm = tangent_mismatch(solver, shear_and_compression(3), 1e-8);
    std::printf("relative mismatch %.3e\n", mm.relative);
    EXPECT_LT(mm.relative, 1e-6);
    EXPECT_EQ(solver.counters().tangent_fallbacks, 0);
}

TEST(Tangent, HypoplasticityWithIntergranularStrainMatchesFiniteDifferencesPlaneStrain) {
    auto solver = hypo_block(2, true, 1e-3);
    const auto mm = tangent_mismatch(solver, shear_and_compression(2), 1e-8);
    std::printf("relative mismatch %.3e\n", mm.relative);
    EXPECT_LT(mm.relative, 1e-6);
}

TEST(Tangent, FixedSubstepSchemeGapShrinksWithTheIntegrationTolerance) {
    // Equal fixed substeps under-resolve the fast intergranular-strain transition that the
    // adaptive update resolves, so that scheme's gap is set by the substep size.
    auto coarse = hypo_block(3, true, 1e-3, true);
    auto fine = hypo_block(3, true, 1e-5, true);
    const auto a = tangent_mismatch(coarse, shear_and_compression(3), 1e-8);
    const auto b = tangent_mismatch(fine, shear_and_compression(3), 1e-8);
    std::printf("fixed-substep scheme: relative mismatch %.3e (tol 1e-3), %.3e (tol 1e-5)\n",
                a.relative, b.relative);
    EXPECT_GT(a.relative, 1e-3);
    EXPECT_LT(a.relative, 0.2);
    EXPECT_LT(b.relative, a.relative / 5.0);
}
