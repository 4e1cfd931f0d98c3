// The contact engine's Jacobian columns (paper Eq. 37: forward differences of the whole
// Algorithm 1 with theta = sqrt(EPS) per displacement component of slave and master) against
// central differences of the update itself, computed independently by calling interface_update
// with the inputs shifted in the engine's conventions (t_N = t_N0 + k_N delta g_N, gap
// g = x(1) - x(2), tangential increment master minus slave) and the base's sub-increment count.
//
// What to expect: Eq. 37 is a forward difference, so it carries a truncation error
// theta |f''| / 2. For the tangential rows the curvature scale is the tangential increment
// itself (the incrementally nonlinear models are not smooth at dg = 0), so the relative error is
// of order theta / |dg|: measured 3e-4 .. 1e-3 in 2D, up to 6.8e-3 in 3D where one tangential
// component is only ~1.2e-6 m (theta / 1.2e-6 = 1.2e-2). Tolerance 2e-2 (3x the largest
// measurement). The slave and master columns of one direction are forward differences at
// +theta and -theta of the same gap component, so their half difference is a central
// difference: it must agree with the reference to O(theta^2) (measured <= 6e-5 with fixed
// sub-increments, <= 2.7e-4 adaptive; tolerance 1e-3, still below Eq. 37's own truncation
// error), which checks the engine's sign and frame conventions far more tightly than Eq. 37
// alone can.
//
// Noise: the differences see every discontinuity of the update within theta = 1.5e-8 m. Two
// were found with adaptive (few, large) sub-increments: the rate Newton Jacobian leaves a
// residual of ~1e-3 even after the polishing step, so the iteration count changes between
// lanes (jumps of 1.4e-2 kPa in tau, Sanisand, up to 40 % error in a column), and the model's
// own adaptive substep count changes between lanes (jumps ~ the model tolerance). The adaptive
// cases below therefore use the perturbation Newton Jacobian and a model tolerance of 1e-5.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "engine/contact_update.hpp"
#include "tests/engine/interface_fixtures.hpp"

using namespace ifsim;
using namespace ifsim::test;

namespace {

struct ColumnErrors {
    double eq37 = 0.0;    // Eq. 37 columns vs central differences, tangential rows
    double central = 0.0; // (J_slave - J_master) / 2 vs central differences, tangential rows
    double normal = 0.0;  // normal row vs k_N n (exact for a penalty)
    bool ok = true;
};

// Two points in one engine call (varied increments and targets, the same tilted frame), each
// compared with its own central differences. With reference = false only the exact penalty row
// is checked (schemes that are not the derivative of the update).
template <class M>
ColumnErrors jacobian_errors(const typename M::Params& mp, const StateVec<double, M::n_state>& y,
                             int ndim, const ContactOptions& opt, bool reference = true) {
    const double h = 1.0e-7;
    const Frame fr = tilted_frame(ndim);
    std::vector<PointInput> inputs(2);
    for (int i = 0; i < 2; ++i) {
        inputs[i].dg1 = 1.0e-5 * (1.0 + 0.3 * i);
        inputs[i].dg2 = ndim == 3 ? 4.0e-6 * (1.0 - 0.7 * i) : 0.0;
        inputs[i].t_N = -100.0 - 3.0 * i;
        inputs[i].s_p1 = -52.0 + i;
        inputs[i].s_p2 = -47.0 - i;
    }
    ContactPoints<M> cp(inputs.size(), ndim);
    for (std::size_t i = 0; i < inputs.size(); ++i) {
        cp.set_state(i, y);
        cp.set_frame(i, fr.n.data(), fr.t1.data(), fr.t2.data());
        cp.input(contact_col::t_N)[i] = inputs[i].t_N;
        cp.input(contact_col::k_N)[i] = inputs[i].k_N;
        cp.input(contact_col::dg1)[i] = inputs[i].dg1;
        cp.input(contact_col::dg2)[i] = inputs[i].dg2;
        cp.input(contact_col::s_p1)[i] = inputs[i].s_p1;
        cp.input(contact_col::s_p2)[i] = inputs[i].s_p2;
    }
    ContactEngine<M> engine;
    const ContactReport rep = engine.update(cp, mp, opt);
    ColumnErrors err;
    err.ok = rep.ok();
    for (std::size_t i = 0; i < inputs.size(); ++i) {
        const double n_sub = cp.output(contact_col::subincrements)[i];
        double fd[6][3];
        double scale = 0.0;
        for (int c = 0; c < 2 * ndim && reference; ++c) {
            const int d = c % ndim;
            const double sign = c < ndim ? 1.0 : -1.0; // slave +u: +g; master +u: -g
            std::array<double, 3> gp{0.0, 0.0, 0.0}, gm{0.0, 0.0, 0.0};
            gp[d] = sign * h;
            gm[d] = -sign * h;
            const auto rp =
                direct_update<M>(mp, opt.interface, y, shifted_input(inputs[i], fr, gp, n_sub));
            const auto rm =
                direct_update<M>(mp, opt.interface, y, shifted_input(inputs[i], fr, gm, n_sub));
            err.ok = err.ok && rp.stats.status > 0.5 && rm.stats.status > 0.5;
            const auto tp = rp.traction();
            const auto tm = rm.traction();
            for (int comp = 0; comp < 3; ++comp) {
                fd[c][comp] = (tp[comp] - tm[comp]) / (2.0 * h);
                if (comp > 0) {
                    scale = std::max(scale, std::abs(fd[c][comp]));
                }
            }
        }
        for (int c = 0; c < 2 * ndim; ++c) {
            const int d = c % ndim;
            const double sign = c < ndim ? 1.0 : -1.0;
            const double normal = sign * inputs[i].k_N * fr.n[d];
            err.normal = std::max(err.normal, std::abs(cp.jacobian(i, 0, c) - normal) /
                                                  (inputs[i].k_N * 1.0e-3 + std::abs(normal)));
            for (int comp = 1; comp < 3; ++comp) {
                EXPECT_TRUE(std::isfinite(cp.jacobian(i, comp, c)));
                if (!reference) {
                    continue;
                }
                if (ndim == 2 && comp == 2) {
                    EXPECT_EQ(cp.jacobian(i, comp, c), 0.0); // plane strain: no tau2
                    continue;
                }
                const double ref = std::max(std::abs(fd[c][comp]), 0.01 * scale);
                err.eq37 =
                    std::max(err.eq37, std::abs(cp.jacobian(i, comp, c) - fd[c][comp]) / ref);
                if (c < ndim) {
                    const double half =
                        0.5 * (cp.jacobian(i, comp, c) - cp.jacobian(i, comp, c + ndim));
                    err.central = std::max(err.central, std::abs(half - fd[c][comp]) / ref);
                }
            }
        }
    }
    return err;
}

ContactOptions options(InterfaceFormulation f, int ndim, bool adaptive) {
    ContactOptions opt;
    opt.interface.formulation = f;
    opt.interface.ndim = ndim;
    opt.interface.adaptive = adaptive;
    if (adaptive) {
        // Smooth enough to difference (see the note at the top).
        opt.interface.newton_jacobian = NewtonJacobian::perturbation;
        opt.interface.model.tolerance = 1.0e-5;
    }
    return opt;
}

std::string label(InterfaceFormulation f, int ndim, bool adaptive) {
    return std::string(f == InterfaceFormulation::novel ? "novel" : "stutz") + " ndim " +
           std::to_string(ndim) + (adaptive ? " adaptive" : " fixed");
}

constexpr double kEq37Tol = 2.0e-2;
constexpr double kCentralTol = 1.0e-3;
constexpr double kNormalTol = 1.0e-9;

template <class M>
void check_all(const typename M::Params& mp, const StateVec<double, M::n_state>& y) {
    for (const auto f : {InterfaceFormulation::novel, InterfaceFormulation::stutz}) {
        for (const int ndim : {2, 3}) {
            for (const bool adaptive : {false, true}) {
                SCOPED_TRACE(label(f, ndim, adaptive));
                const auto e = jacobian_errors<M>(mp, y, ndim, options(f, ndim, adaptive));
                ASSERT_TRUE(e.ok);
                EXPECT_LT(e.eq37, kEq37Tol);
                EXPECT_LT(e.normal, kNormalTol);
                EXPECT_LT(e.central, kCentralTol);
            }
        }
    }
}

} // namespace

TEST(ContactJacobian, Eq37MatchesCentralDifferencesHypoplasticity) {
    check_all<Hypoplasticity>(l4c(0.9), hypo_state());
}

TEST(ContactJacobian, Eq37MatchesCentralDifferencesSanisand) {
    check_all<Sanisand>(karlsruhe_sanisand(0.9), sanisand_state());
}

// Adaptive sub-increments with the default settings (rate Newton Jacobian, model tolerance
// 1e-3), hypoplasticity: Eq. 37 stays within its tolerance (measured <= 6.8e-3 for these two
// points, 2.3e-3 for a third point with dg = (1.6e-5, -1.6e-6) m in 2D). The central check is
// not asserted with these defaults: it is noise-dominated for some points (measured 1.9e-3 for
// that third point). Sanisand with these defaults is not asserted at all: a change of the
// Newton iteration count within theta gave 40 % in one column (see the note at the top).
TEST(ContactJacobian, AdaptiveDefaultsHypoplasticity) {
    for (const int ndim : {2, 3}) {
        ContactOptions opt;
        opt.interface.ndim = ndim;
        opt.interface.adaptive = true;
        const auto e = jacobian_errors<Hypoplasticity>(l4c(0.9), hypo_state(), ndim, opt);
        ASSERT_TRUE(e.ok);
        EXPECT_LT(e.eq37, kEq37Tol) << ndim;
        EXPECT_LT(e.normal, kNormalTol) << ndim;
    }
}

// A state sheared close to the peak (hypoplasticity, novel, 3D): the columns still match.
TEST(ContactJacobian, Eq37MatchesAfterShearing) {
    const auto mp = l4c(0.9);
    InterfaceSettings s;
    InterfaceState<double, Hypoplasticity::n_state> st;
    st.y = hypo_state();
    for (int i = 0; i < 10; ++i) {
        InterfaceStats<double> stats;
        interface_update<Hypoplasticity, double>(mp, s, st,
                                                 {-100.0, 2.0e-5, 0.0, -52.0, -47.0, 0.0}, stats);
        ASSERT_EQ(stats.status, lane_status::ok);
    }
    ASSERT_GT(st.y[3], 30.0);
    for (const int ndim : {2, 3}) {
        const auto e = jacobian_errors<Hypoplasticity>(
            mp, st.y, ndim, options(InterfaceFormulation::novel, ndim, false));
        ASSERT_TRUE(e.ok);
        EXPECT_LT(e.eq37, kEq37Tol) << ndim;
        EXPECT_LT(e.central, kCentralTol) << ndim;
        EXPECT_LT(e.normal, kNormalTol) << ndim;
    }
}

// Coarse sub-increments (10x the paper's size). Hypoplasticity integrates each in one substep
// and the columns stay accurate. Sanisand's own adaptive substepping then changes its substep
// count between the base and a perturbed lane (Algorithm 1's sub-increments are pinned by the
// engine, the model's substeps are not), which puts jumps of ~2e-3 kPa into tau: divided by
// theta that is an error of up to 36 % in single columns at the default model tolerance
// (measured). With a model tolerance of 1e-5 the substep counts stay put and the columns agree.
TEST(ContactJacobian, CoarseSubincrementsHypoplasticity) {
    for (const int ndim : {2, 3}) {
        auto opt = options(InterfaceFormulation::novel, ndim, false);
        opt.interface.max_subincrement = 5.0e-5;
        const auto e = jacobian_errors<Hypoplasticity>(l4c(0.9), hypo_state(), ndim, opt);
        ASSERT_TRUE(e.ok);
        EXPECT_LT(e.eq37, kEq37Tol);
        EXPECT_LT(e.central, kCentralTol);
    }
}

TEST(ContactJacobian, CoarseSubincrementsSanisandWithTightModelTolerance) {
    for (const auto f : {InterfaceFormulation::novel, InterfaceFormulation::stutz}) {
        for (const int ndim : {2, 3}) {
            auto opt = options(f, ndim, false);
            opt.interface.max_subincrement = 5.0e-5;
            opt.interface.model.tolerance = 1.0e-5;
            const auto e =
                jacobian_errors<Sanisand>(karlsruhe_sanisand(0.9), sanisand_state(), ndim, opt);
            ASSERT_TRUE(e.ok);
            EXPECT_LT(e.eq37, kEq37Tol) << label(f, ndim, false);
            EXPECT_LT(e.central, kCentralTol) << label(f, ndim, false);
        }
    }
}

// The scalar path gives the same columns as the SIMD path (the lanes of a batch are
// independent; xsimd and libm round differently, and theta amplifies that by 1/theta).
TEST(ContactJacobian, ScalarPathGivesTheSameColumns) {
    for (const int ndim : {2, 3}) {
        auto opt = options(InterfaceFormulation::novel, ndim, false);
        opt.simd = false;
        const auto e = jacobian_errors<Hypoplasticity>(l4c(0.9), hypo_state(), ndim, opt);
        ASSERT_TRUE(e.ok);
        EXPECT_LT(e.eq37, kEq37Tol);
        EXPECT_LT(e.central, kCentralTol);
        EXPECT_LT(e.normal, kNormalTol);
    }
}

// The other two schemes keep the exact penalty row and finite tangential columns (on the
// tilted frame, two points, all lanes of the full scheme's fixed-point iterations). They are not
// the derivative of the update: Eq. B3 keeps only the first term of Eq. B2 (measured deviation
// from the central differences 4e-2 .. 3 relative); the full perturbation of Eqs. 39-40 starts
// its perturbed lanes from the committed state moved along the derivative of the end state,
// which the update (integrated from the committed state over the whole increment) already
// contains, so its tangential columns come out about twice the derivative (measured deviation
// 0.85 .. 2.6 relative).
TEST(ContactJacobian, OtherSchemesKeepThePenaltyRow) {
    for (const auto scheme : {ContactJacobian::analytical, ContactJacobian::full_perturbation}) {
        for (const int ndim : {2, 3}) {
            auto opt = options(InterfaceFormulation::novel, ndim, false);
            opt.jacobian = scheme;
            const auto e =
                jacobian_errors<Hypoplasticity>(l4c(0.9), hypo_state(), ndim, opt, false);
            ASSERT_TRUE(e.ok);
            EXPECT_LT(e.normal, kNormalTol);
        }
    }
}
