// One element in oedometric compression with hypoplasticity (lateral displacements fixed)
// against the point-level element test (engine/element_test_driver.hpp): the finite element and the
// material engine must give the same stress path, by prescribed displacement (hex8 and
// plane-strain quad4) and by a top pressure on a rigid plate (stress control).
#include <gtest/gtest.h>

#include "engine/element_test_driver.hpp"
#include "tests/fem/fem_test_support.hpp"

using namespace ifsim;
using namespace ifsim::fem;
using namespace ifsim::fem::testing;

namespace {

const Sym<double> iso100 = {-100.0, -100.0, -100.0, 0.0, 0.0, 0.0};

std::vector<ElementRow> element_test_rows(const std::vector<double>& y0, const ElementStage& st) {
    std::vector<ElementRow> rows;
    ElementTestSettings s;
    s.newton_tolerance = 1e-12;
    const auto r = run_element_test(karlsruhe(), y0, {st}, s,
                                    [&](const ElementRow& row) { rows.push_back(row); });
    EXPECT_TRUE(r.ok) << r.reason;
    return rows;
}

// Stress of every integration point after each increment.
struct Recorder {
    const StaticSolver* solver = nullptr;
    std::vector<std::vector<std::vector<double>>> states; // increment -> point -> state
    std::vector<double> top_displacement;
    int top_dof = 0;
    void operator()(const IncrementInfo&) {
        std::vector<std::vector<double>> pts;
        for (int q = 0; q < solver->points_per_element(); ++q) {
            pts.push_back(solver->state(0, q));
        }
        states.push_back(pts);
        top_displacement.push_back(solver->displacement()[static_cast<std::size_t>(top_dof)]);
    }
};

void compare_prescribed(int dim) {
    const double strain = 0.02; // 2 % vertical compression in 20 increments
    const int steps = 20;
    const int v = dim == 2 ? 1 : 2; // vertical Voigt component and direction
    const auto y0 = hypo_state(iso100, 0.75);
    Mesh m = dim == 2 ? rectangle_mesh({1.0, 1.0, 1, 1}) : box_mesh({1.0, 1.0, 1.0, 1, 1, 1});
    StaticSolver solver(m, {material(karlsruhe(), y0)}, {});
    Stage st;
    st.steps = steps;
    st.displacements = {
        {"left", 0, 0.0}, {"right", 0, 0.0}, {"bottom", v, 0.0}, {"top", v, -strain}};
    if (dim == 3) {
        st.displacements.push_back({"front", 1, 0.0});
        st.displacements.push_back({"back", 1, 0.0});
    }
    Recorder rec{&solver, {}, {}, 0};
    const auto res = solver.run_stage(st, std::ref(rec));
    ASSERT_TRUE(res.ok) << res.reason;
    EXPECT_EQ(solver.counters().newton_iterations, 0); // every DOF is prescribed

    ElementStage es;
    es.steps = steps;
    es.change[static_cast<std::size_t>(v)] = -strain;
    const auto rows = element_test_rows(y0, es);
    ASSERT_EQ(rows.size(), static_cast<std::size_t>(steps + 1));
    ASSERT_EQ(rec.states.size(), static_cast<std::size_t>(steps));
    // Largest deviation of stress (relative to the vertical stress) and void ratio per increment.
    std::vector<double> dev;
    for (int k = 0; k < steps; ++k) {
        const auto& ref = rows[static_cast<std::size_t>(k + 1)].state;
        double d = 0.0;
        for (const auto& y : rec.states[static_cast<std::size_t>(k)]) {
            for (std::size_t i = 0; i < 7; ++i) {
                const double scale = i < 6 ? std::abs(ref[static_cast<std::size_t>(v)]) : 1.0;
                d = std::max(d, std::abs(y[i] - ref[i]) / scale);
            }
        }
        dev.push_back(d);
    }
    // The strain from nodal displacements equals the prescribed one to rounding (1 ulp), so the
    // first increment agrees to rounding; later a substep accept/reject decision may flip on
    // that last bit and the paths then differ by up to the integration tolerance (1e-3).
    EXPECT_LT(dev.front(), 1e-12);
    for (int k = 0; k < steps; ++k) {
        EXPECT_LT(dev[static_cast<std::size_t>(k)], 1e-3) << "increment " << k + 1;
    }
    // The path went somewhere: the vertical stress grew several-fold.
    EXPECT_LT(rows.back().state[static_cast<std::size_t>(v)], -300.0);
}

} // namespace

TEST(OedometerElement, Hex8MatchesElementTest) {
    compare_prescribed(3);
}

TEST(OedometerElement, PlaneStrainQuad4MatchesElementTest) {
    compare_prescribed(2);
}

TEST(OedometerElement, TopPressureOnRigidPlateMatchesStressControlledElementTest) {
    const auto y0 = hypo_state(iso100, 0.75);
    const int steps = 10;
    Mesh m = box_mesh({1.0, 1.0, 1.0, 1, 1, 1});
    SolverSettings settings;
    settings.residual_tolerance = 1e-12;
    StaticSolver solver(m, {material(karlsruhe(), y0)}, settings);
    Stage st;
    st.steps = steps;
    st.displacements = {{"left", 0, 0.0},
                        {"right", 0, 0.0},
                        {"front", 1, 0.0},
                        {"back", 1, 0.0},
                        {"bottom", 2, 0.0}};
    st.equal_displacements = {{"top", 2}};
    st.pressures = {{"top", 100.0, 400.0}}; // in equilibrium with the initial -100 kPa
    Recorder rec{&solver, {}, {}, 0};
    rec.top_dof = m.node_set("top").front() * 3 + 2;
    const auto res = solver.run_stage(st, std::ref(rec));
    ASSERT_TRUE(res.ok) << res.reason;
    EXPECT_GT(solver.counters().newton_iterations, steps); // the plate is a real unknown

    ElementStage es;
    es.steps = steps;
    es.stress_controlled[2] = true;
    es.change[2] = -300.0;
    const auto rows = element_test_rows(y0, es);
    ASSERT_EQ(rec.states.size(), static_cast<std::size_t>(steps));
    for (int k = 0; k < steps; ++k) {
        const auto& ref = rows[static_cast<std::size_t>(k + 1)];
        EXPECT_NEAR(rec.top_displacement[static_cast<std::size_t>(k)], ref.strain[2], 1e-9)
            << "increment " << k + 1;
        for (const auto& y : rec.states[static_cast<std::size_t>(k)]) {
            for (int i = 0; i < 7; ++i) {
                EXPECT_NEAR(y[static_cast<std::size_t>(i)], ref.state[static_cast<std::size_t>(i)],
                            1e-6 * std::max(1.0, std::abs(ref.state[2])))
                    << "increment " << k + 1 << " component " << i;
            }
        }
        EXPECT_NEAR(rec.states[static_cast<std::size_t>(k)][0][2], -100.0 - 30.0 * (k + 1), 1e-8);
    }
}
