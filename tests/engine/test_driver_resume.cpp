// Resuming the point-level drivers (checkpoint and resume, docs/scenes.md): a run restarted
// from the position reported after step k writes, from step k + 1 on, the rows of the
// uninterrupted run bit for bit: element tests (hypoplasticity and Sanisand, mixed control,
// resumed inside a stage and at a stage's end) and interface tests (novel, Stutz, Coulomb;
// CNS, where the spring, slip and first guesses are carried).
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#define IFSIM_TEST_ENGINE_HELPERS
#include "engine/element_test_driver.hpp"
#include "tests/engine/interface_fixtures.hpp"

using namespace ifsim;
using namespace ifsim::test;

namespace {

// Bitwise equality of doubles (NaN-safe, -0 differs from +0).
bool same_bits(double a, double b) {
    return std::memcmp(&a, &b, sizeof a) == 0;
}

void expect_same(const ElementRow& a, const ElementRow& b) {
    EXPECT_EQ(a.step, b.step);
    EXPECT_EQ(a.stage, b.stage);
    for (int j = 0; j < 6; ++j) {
        EXPECT_TRUE(same_bits(a.strain[j], b.strain[j])) << "strain " << j;
    }
    ASSERT_EQ(a.state.size(), b.state.size());
    for (std::size_t k = 0; k < a.state.size(); ++k) {
        EXPECT_TRUE(same_bits(a.state[k], b.state[k])) << "state " << k;
    }
}

void expect_same(const InterfaceRow& a, const InterfaceRow& b) {
    EXPECT_EQ(a.step, b.step);
    EXPECT_EQ(a.stage, b.stage);
    EXPECT_EQ(a.newton_iterations, b.newton_iterations);
    const double va[] = {a.u_t1,           a.u_n,        a.t_n,        a.t_t1,       a.s_n,
                         a.s_p1,           a.s_p2,       a.eps_n,      a.eps_p1,     a.gamma1,
                         a.band_thickness, a.sample_s11, a.sample_s22, a.sample_s12, a.e_interface,
                         a.e_sample,       a.slip1};
    const double vb[] = {b.u_t1,           b.u_n,        b.t_n,        b.t_t1,       b.s_n,
                         b.s_p1,           b.s_p2,       b.eps_n,      b.eps_p1,     b.gamma1,
                         b.band_thickness, b.sample_s11, b.sample_s22, b.sample_s12, b.e_interface,
                         b.e_sample,       b.slip1};
    for (std::size_t k = 0; k < std::size(va); ++k) {
        EXPECT_TRUE(same_bits(va[k], vb[k])) << "column " << k << ": " << va[k] << " vs " << vb[k];
    }
}

// Runs uninterrupted, keeping the position after every step, then resumes from each step in
// `from` and compares the rows that follow.
void check_element_resume(const MaterialChoice& m, const std::vector<double>& y0,
                          const std::vector<ElementStage>& stages, const std::vector<int>& from) {
    ElementTestSettings s;
    std::vector<ElementRow> whole;
    std::vector<ElementTestPosition> positions;
    const auto r = run_element_test(
        m, y0, stages, s, [&](const ElementRow& row) { whole.push_back(row); }, nullptr,
        [&](const ElementTestPosition& p) { positions.push_back(p); });
    ASSERT_TRUE(r.ok) << r.reason;
    ASSERT_EQ(positions.size() + 1, whole.size());
    for (int k : from) {
        SCOPED_TRACE(k);
        std::vector<ElementRow> rest;
        const auto rr = run_element_test(
            m, y0, stages, s, [&](const ElementRow& row) { rest.push_back(row); },
            &positions[static_cast<std::size_t>(k - 1)]);
        ASSERT_TRUE(rr.ok) << rr.reason;
        ASSERT_EQ(rest.size() + static_cast<std::size_t>(k) + 1, whole.size()); // no row 0
        for (std::size_t i = 0; i < rest.size(); ++i) {
            expect_same(rest[i], whole[static_cast<std::size_t>(k) + 1 + i]);
        }
    }
}

ElementStage stage(int steps, Sym<double> change, std::array<bool, 6> stress_controlled) {
    ElementStage st;
    st.steps = steps;
    st.change = change;
    st.stress_controlled = stress_controlled;
    return st;
}

} // namespace

// Drained triaxial compression then unloading (stress-controlled lateral components): resumed
// in the middle of the first stage, at its last step (the next stage starts from the resumed
// stress) and in the second.
TEST(DriverResume, ElementTestContinuesBitForBit) {
    const std::array<bool, 6> drained = {false, true, true, false, false, false};
    const std::vector<ElementStage> stages = {stage(12, {-0.01, 0, 0, 0, 0, 0}, drained),
                                              stage(8, {0.004, 0, 0, 0, 0, 0}, drained)};
    HypoplasticityParams hp = parameter_sets::hypoplasticity_karlsruhe();
    hp.prepare();
    std::vector<double> yh(Hypoplasticity::n_state, 0.0);
    yh[0] = yh[1] = yh[2] = -100.0;
    yh[6] = 0.7;
    check_element_resume(hp, yh, stages, {5, 12, 15});
    check_element_resume(karlsruhe_sanisand(1.0), as_vector(sanisand_state(-100.0, 1.0, 0.75)),
                         stages, {3, 12, 19});
}

// Interface tests under CNS with a reversal: every formulation continues bit for bit.
TEST(DriverResume, InterfaceTestContinuesBitForBit) {
    for (const auto f : {InterfaceFormulation::novel, InterfaceFormulation::stutz,
                         InterfaceFormulation::coulomb}) {
        SCOPED_TRACE(static_cast<int>(f));
        InterfaceTestSpec spec = l4c_spec(f, 0.9, -200.0);
        spec.control = NormalControl::constant_stiffness;
        spec.normal_stiffness = 4.0e5;
        spec.coulomb.friction_coefficient = 0.5;
        spec.coulomb.tangential_stiffness = 4.0e5;
        spec.stages = {{8, 5.0e-4, 0.0}, {6, -4.0e-4, 0.0}};
        std::vector<InterfaceRow> whole;
        std::vector<InterfaceTestPosition> positions;
        const auto r = run_interface_test(
            spec, [&](const InterfaceRow& row) { whole.push_back(row); }, nullptr,
            [&](const InterfaceTestPosition& p) { positions.push_back(p); });
        ASSERT_TRUE(r.ok) << r.reason;
        ASSERT_EQ(positions.size() + 1, whole.size());
        for (int k : {3, 8, 11}) {
            SCOPED_TRACE(k);
            std::vector<InterfaceRow> rest;
            const auto rr = run_interface_test(
                spec, [&](const InterfaceRow& row) { rest.push_back(row); },
                &positions[static_cast<std::size_t>(k - 1)]);
            ASSERT_TRUE(rr.ok) << rr.reason;
            ASSERT_EQ(rest.size() + static_cast<std::size_t>(k) + 1, whole.size());
            for (std::size_t i = 0; i < rest.size(); ++i) {
                expect_same(rest[i], whole[static_cast<std::size_t>(k) + 1 + i]);
            }
        }
    }
}

// A position of the wrong model is refused with a message, not run.
TEST(DriverResume, RefusesAStateOfTheWrongLength) {
    InterfaceTestSpec spec = l4c_spec(InterfaceFormulation::novel);
    spec.stages = {{2, 1.0e-4, 0.0}};
    InterfaceTestPosition p;
    p.sample_state = spec.sample_state;
    p.interface_state = {1.0, 2.0};
    EXPECT_THROW(run_interface_test(
                     spec, [](const InterfaceRow&) {}, &p),
                 std::invalid_argument);
    ElementTestPosition e;
    e.state = {1.0, 2.0, 3.0};
    EXPECT_THROW(run_element_test(
                     LinearElasticParams{2.0e4, 0.3}, {-50, -50, -50, 0, 0, 0, 0.7}, {},
                     ElementTestSettings{}, [](const ElementRow&) {}, &e),
                 std::invalid_argument);
}
