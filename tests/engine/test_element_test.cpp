// The element-test driver: mixed control against closed-form elasticity, tangent choices,
// scalar against SIMD path, and failures that name their step.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/element_test_driver.hpp"
#include "kernels/parameter_sets.hpp"

using namespace ifsim;

namespace {

std::vector<ElementRow> run(const MaterialChoice& m, const std::vector<double>& y0,
                            const std::vector<ElementStage>& stages, const ElementTestSettings& s,
                            ElementTestResult* res = nullptr) {
    std::vector<ElementRow> rows;
    auto r =
        run_element_test(m, y0, stages, s, [&](const ElementRow& row) { rows.push_back(row); });
    if (res) {
        *res = r;
    } else {
        EXPECT_TRUE(r.ok) << r.reason;
    }
    return rows;
}

ElementStage drained_triaxial(double deps11, int steps) {
    ElementStage st;
    st.steps = steps;
    st.change = {deps11, 0.0, 0.0, 0.0, 0.0, 0.0};
    st.stress_controlled = {false, true, true, false, false, false};
    return st;
}

std::vector<double> hypo_state(double e) {
    std::vector<double> y(Hypoplasticity::n_state, 0.0);
    y[0] = -100.0;
    y[1] = y[2] = -100.0;
    y[6] = e;
    return y;
}

HypoplasticityParams karlsruhe() {
    auto p = parameter_sets::hypoplasticity_karlsruhe();
    p.prepare();
    return p;
}

} // namespace

TEST(ElementTest, DrainedTriaxialOnLinearElasticityIsHookesLaw) {
    LinearElasticParams p{2.0e4, 0.3};
    std::vector<double> y0 = {-50.0, -50.0, -50.0, 0.0, 0.0, 0.0, 0.7};
    ElementTestSettings s;
    s.newton_tolerance = 1e-13; // demand the exact solution of the linear problem
    const auto rows = run(p, y0, {drained_triaxial(-0.01, 10)}, s);
    ASSERT_EQ(rows.size(), 11u);
    const auto& last = rows.back();
    EXPECT_NEAR(last.strain[0], -0.01, 1e-15);
    EXPECT_NEAR(last.strain[1], 0.3 * 0.01, 1e-12); // -nu eps11
    EXPECT_NEAR(last.strain[2], 0.3 * 0.01, 1e-12);
    EXPECT_NEAR(last.state[0], -50.0 - 2.0e4 * 0.01, 1e-8); // E eps11 at constant lateral stress
    EXPECT_NEAR(last.state[1], -50.0, 1e-8);
}

TEST(ElementTest, StressTargetsAreMetInEveryStep) {
    ElementTestSettings s;
    std::vector<ElementStage> st = {drained_triaxial(-0.02, 40)};
    ElementStage iso;
    iso.steps = 20;
    iso.stress_controlled = {true, true, true, false, false, false};
    iso.change = {-100.0, -100.0, -100.0, 0.0, 0.0, 0.0};
    st.insert(st.begin(), iso);
    const auto rows = run(karlsruhe(), hypo_state(0.62), st, s);
    for (const auto& r : rows) {
        if (r.stage == 1) {
            const double target = -100.0 - 100.0 * r.step / 20.0;
            EXPECT_NEAR(r.state[0], target, 1e-6 * 200.0);
            EXPECT_NEAR(r.state[2], target, 1e-6 * 200.0);
        } else if (r.stage == 2) {
            EXPECT_NEAR(r.state[1], -200.0, 1e-5);
            EXPECT_NEAR(r.state[2], -200.0, 1e-5);
        }
    }
}

TEST(ElementTest, RateTangentAndPerturbationTangentReachTheSameSolution) {
    ElementTestSettings a, b;
    b.tangent = TangentKind::rate;
    ElementTestResult ra, rb;
    const auto rows_a = run(karlsruhe(), hypo_state(0.62), {drained_triaxial(-0.05, 50)}, a, &ra);
    const auto rows_b = run(karlsruhe(), hypo_state(0.62), {drained_triaxial(-0.05, 50)}, b, &rb);
    ASSERT_TRUE(ra.ok && rb.ok);
    for (std::size_t i = 0; i < rows_a.size(); ++i) {
        for (int k = 0; k < 6; ++k) {
            EXPECT_NEAR(rows_a[i].state[k], rows_b[i].state[k], 1e-5 * 400.0);
        }
    }
    // The consistent tangent needs fewer Newton iterations than the rate stiffness.
    EXPECT_LT(ra.counters.newton_iterations, rb.counters.newton_iterations);
}

TEST(ElementTest, ScalarAndSimdPathsAgreeToRoundOff) {
    ElementTestSettings simd_s, scalar_s;
    scalar_s.update.simd = false;
    const auto st = std::vector<ElementStage>{drained_triaxial(-0.1, 100)};
    const auto a = run(karlsruhe(), hypo_state(0.60), st, simd_s);
    const auto b = run(karlsruhe(), hypo_state(0.60), st, scalar_s);
    ASSERT_EQ(a.size(), b.size());
    double worst = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        for (int k = 0; k < 7; ++k) {
            worst = std::max(worst, std::abs(a[i].state[k] - b[i].state[k]) /
                                        (1.0 + std::abs(b[i].state[k])));
        }
    }
    // Far inside the integration tolerance (1e-3) even where round-off flips a step decision
    // (the stress's substeps and h's own sub-steps: measured 1.7e-6 .. 2.8e-6).
    EXPECT_LT(worst, 1e-5);
}

TEST(ElementTest, UnreachableTensionStopsWithAReasonNamingTheStep) {
    ElementTestSettings s;
    s.max_newton_iterations = 15;
    ElementStage pull;
    pull.steps = 10;
    pull.stress_controlled = {true, true, true, false, false, false};
    pull.change = {200.0, 200.0, 200.0, 0.0, 0.0, 0.0}; // from -100 to +100 kPa: tension
    ElementTestResult res;
    const auto rows = run(karlsruhe(), hypo_state(0.62), {pull}, s, &res);
    EXPECT_FALSE(res.ok);
    EXPECT_NE(res.reason.find("step"), std::string::npos) << res.reason;
    for (const auto& r : rows) {
        for (double v : r.state) {
            EXPECT_TRUE(std::isfinite(v));
        }
    }
}

TEST(ElementTest, WrongStateLengthIsAnError) {
    ElementTestSettings s;
    EXPECT_THROW(run_element_test(karlsruhe(), {1.0, 2.0}, {}, s, [](const ElementRow&) {}),
                 std::invalid_argument);
}
