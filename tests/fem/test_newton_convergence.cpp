// Newton convergence: one iteration for linear elasticity with the exact (rate) tangent;
// quadratic in the last iterations for hypoplasticity with the perturbation tangent (the
// residual sequences are printed); the cheap rate tangent converges only linearly there.
#include <gtest/gtest.h>

#include <cstdio>

#include "tests/fem/fem_test_support.hpp"

using namespace ifsim;
using namespace ifsim::fem;
using namespace ifsim::fem::testing;

namespace {

void print(const char* what, const IncrementInfo& info) {
    std::printf("%s, step %d:", what, info.step);
    for (double r : info.residuals) {
        std::printf(" %.2e", r);
    }
    std::printf("\n");
}

Stage shear_under_pressure(int dim, int steps) {
    const int v = dim - 1;
    Stage st;
    st.steps = steps;
    st.displacements = {{"bottom", 0, 0.0}, {"bottom", v, 0.0}, {"top", 0, 2e-3}};
    if (dim == 3) {
        st.displacements.push_back({"bottom", 1, 0.0});
        st.displacements.push_back({"front", 1, 0.0});
        st.displacements.push_back({"back", 1, 0.0});
    }
    st.equal_displacements = {{"top", v}};
    st.pressures = {{"top", 60.0, 90.0}};
    return st;
}

std::vector<IncrementInfo> run_hypo(TangentKind kind, bool igs, int max_iterations) {
    Mesh m = box_mesh({1.0, 0.5, 1.0, 2, 1, 2});
    distort(m, 0.1, 0.5);
    auto p = karlsruhe();
    p.intergranular_strain = igs;
    auto mat = material(p, hypo_state({-30, -30, -60, 0, 0, 0}, 0.65));
    SolverSettings s;
    s.tangent.kind = kind;
    s.residual_tolerance = 1e-12; // follow the iteration to the rounding floor
    s.max_iterations = max_iterations;
    s.max_cuts = 0;
    StaticSolver solver(m, {mat}, s);
    std::vector<IncrementInfo> infos;
    Stage st = shear_under_pressure(3, 2);
    // Constant confinement in equilibrium with the initial state; the top plate shears.
    st.pressures = {{"top", 60.0, 60.0}, {"left", 30.0, 30.0}, {"right", 30.0, 30.0}};
    const auto res =
        solver.run_stage(st, [&](const IncrementInfo& info) { infos.push_back(info); });
    EXPECT_TRUE(res.ok) << res.reason;
    return infos;
}

} // namespace

TEST(NewtonConvergence, LinearElasticityConvergesInOneIteration) {
    for (int dim : {2, 3}) {
        Mesh m = dim == 2 ? rectangle_mesh({2.0, 1.0, 6, 3}) : box_mesh({1.0, 1.0, 1.0, 3, 2, 3});
        distort(m, 0.15, 0.3);
        SolverSettings s;
        s.tangent.kind = TangentKind::rate; // the exact tangent of Hooke's law
        s.predictor = fem::Predictor::zero;
        StaticSolver solver(m, {material(LinearElasticParams{2e4, 0.3}, elastic_state())}, s);
        std::vector<IncrementInfo> infos;
        const auto res =
            solver.run_stage(shear_under_pressure(dim, 3), [&](const IncrementInfo& i) {
                infos.push_back(i);
                print(dim == 2 ? "linear elastic 2D" : "linear elastic 3D", i);
            });
        ASSERT_TRUE(res.ok) << res.reason;
        ASSERT_EQ(infos.size(), 3u);
        for (const auto& info : infos) {
            ASSERT_EQ(info.residuals.size(), 2u);
            EXPECT_GT(info.residuals[0], 1e-3);
            EXPECT_LT(info.residuals[1], 1e-13);
        }
        EXPECT_EQ(solver.counters().newton_iterations, 3);
    }
}

TEST(NewtonConvergence, HypoplasticityWithPerturbationTangentIsQuadratic) {
    for (bool igs : {true, false}) {
        const auto infos = run_hypo(TangentKind::perturbation, igs, 12);
        ASSERT_EQ(infos.size(), 2u);
        int quadratic_pairs = 0;
        for (const auto& info : infos) {
            print(igs ? "hypoplasticity + IGS, perturbation tangent"
                      : "hypoplasticity, perturbation tangent",
                  info);
            const auto& r = info.residuals;
            EXPECT_LE(r.size(), 8u);
            EXPECT_LT(r.back(), 1e-12);
            // Quadratic: r_{k+1} <= C r_k^2 once r_k is small (C ~ 10 here), above the
            // rounding floor.
            for (std::size_t k = 0; k + 1 < r.size(); ++k) {
                if (r[k] < 1e-2 && r[k] > 1e-7) {
                    EXPECT_LT(r[k + 1], 100.0 * r[k] * r[k]) << "iteration " << k;
                    ++quadratic_pairs;
                }
            }
        }
        EXPECT_GE(quadratic_pairs, 2);
    }
}

TEST(NewtonConvergence, RateTangentConvergesOnlyLinearly) {
    const auto pert = run_hypo(TangentKind::perturbation, false, 12);
    const auto rate = run_hypo(TangentKind::rate, false, 40);
    ASSERT_EQ(rate.size(), 2u);
    for (std::size_t k = 0; k < rate.size(); ++k) {
        print("hypoplasticity, rate tangent", rate[k]);
        EXPECT_GT(rate[k].residuals.size(), pert[k].residuals.size());
    }
}
