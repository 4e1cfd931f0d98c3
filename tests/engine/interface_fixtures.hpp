#pragma once
// Shared set-up of the interface-kernel and contact-engine tests: the paper's parameter sets with
// a roughness factor, interface start states (paper §5.1: D_r0 = 0.88, K0 = 0.5, intergranular
// strain mobilised in the shearing direction), a tilted local frame, and the direct evaluation
// of Algorithm 1 for one point. Kernel headers only, so both test folders can use it; the
// engine helpers (Jacobian columns against central differences, the point-level interface test)
// are compiled only where IFSIM_TEST_ENGINE_HELPERS is defined before the include.

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "kernels/interface_algorithm1.hpp"
#include "kernels/parameter_sets.hpp"

namespace ifsim::test {

// Table 1 (L4C) with roughness kappa (Eqs. 30-32).
inline HypoplasticityParams l4c(double kappa = 0.9) {
    HypoplasticityParams p = parameter_sets::hypoplasticity_l4c();
    p.roughness = kappa;
    p.prepare();
    return p;
}

// Table 4 (Karlsruhe sand, Sanisand) with roughness kappa (Eqs. 33-35).
inline SanisandParams karlsruhe_sanisand(double kappa = 0.9) {
    SanisandParams p = parameter_sets::sanisand_karlsruhe();
    p.roughness = kappa;
    p.prepare();
    return p;
}

// e0 of the monotonic tests of §5.1: D_r0 = 0.88 between e_c0 and e_d0 of Table 1.
inline double l4c_void_ratio(double relative_density = 0.88) {
    const HypoplasticityParams p = parameter_sets::hypoplasticity_l4c();
    return p.e_c0 - relative_density * (p.e_c0 - p.e_d0);
}

// Interface (or sample) state in local axes (1 = n, 2 = t1, 3 = t2): sigma_N = t_N, in-plane
// stresses K0 t_N, intergranular strain fully mobilised in the t1 shearing direction (tensor
// components: h_12 = h_21 = R / sqrt 2, |h| = R).
inline StateVec<double, Hypoplasticity::n_state> hypo_state(double t_N = -100.0, double k0 = 0.5,
                                                            double e = l4c_void_ratio()) {
    StateVec<double, Hypoplasticity::n_state> y{};
    y[0] = t_N;
    y[1] = y[2] = k0 * t_N;
    y[6] = e;
    y[Hypoplasticity::h_index + 3] = parameter_sets::hypoplasticity_l4c().R / std::sqrt(2.0);
    return y;
}

inline StateVec<double, Sanisand::n_state> sanisand_state(double t_N = -100.0, double k0 = 0.5,
                                                          double e = 0.75) {
    return Sanisand::initial_state({t_N, k0 * t_N, k0 * t_N, 0.0, 0.0, 0.0}, e);
}

inline std::vector<double> as_vector(const auto& y) {
    return std::vector<double>(y.begin(), y.end());
}

// A local frame that is not aligned with the global axes, so every projection of the gap onto
// n, t1, t2 is exercised. 2D: rotation in the 1-2 plane, t2 = e3 out of plane.
struct Frame {
    std::array<double, 3> n, t1, t2;
};
inline Frame tilted_frame(int ndim) {
    const double a = 0.3, b = 0.2;
    Frame f;
    f.n = {std::cos(a), std::sin(a), 0.0};
    f.t1 = {-std::sin(a), std::cos(a), 0.0};
    f.t2 = {0.0, 0.0, 1.0};
    if (ndim == 3) {
        // Rotate n and t2 about t1.
        f.n = {std::cos(a) * std::cos(b), std::sin(a) * std::cos(b), std::sin(b)};
        f.t2 = {-std::cos(a) * std::sin(b), -std::sin(a) * std::sin(b), std::cos(b)};
    }
    return f;
}

// Inputs of one contact point in the engine's conventions: t_N is the penalty traction with
// k_N = d t_N / d g_N, gap g = x(1) - x(2) (Eq. 7), tangential gap increment master minus slave
// (Eq. A13).
struct PointInput {
    double t_N = -100.0, k_N = 2.0e5;
    double dg1 = 1.0e-5, dg2 = 4.0e-6;
    double s_p1 = -52.0, s_p2 = -47.0;
    double dsp1_dtn = 0.0, dsp2_dtn = 0.0; // in-plane targets tied to t_N (contact_col)
};

// The input of Algorithm 1 after a change dgap of the gap vector g (global components), i.e.
// after a slave displacement +dgap or a master displacement -dgap.
inline InterfaceInput<double> shifted_input(const PointInput& p, const Frame& f,
                                            const std::array<double, 3>& dgap, double forced) {
    double gn = 0.0, g1 = 0.0, g2 = 0.0;
    for (int d = 0; d < 3; ++d) {
        gn += dgap[d] * f.n[d];
        g1 += dgap[d] * f.t1[d];
        g2 += dgap[d] * f.t2[d];
    }
    const double dt_N = p.k_N * gn;
    return {p.t_N + dt_N,
            p.dg1 - g1,
            p.dg2 - g2,
            p.s_p1 + p.dsp1_dtn * dt_N,
            p.s_p2 + p.dsp2_dtn * dt_N,
            forced};
}

// One scalar evaluation of Algorithm 1 from a start state (model state y, interface strains).
template <class M>
struct DirectResult {
    InterfaceState<double, M::n_state> st;
    InterfaceStats<double> stats;
    std::array<double, 3> traction() const { return {st.y[0], st.y[3], st.y[4]}; }
    // The traction the contact engine transmits (docs/interface.md): an open point (t_N above
    // -open_threshold) gives the penalty's t_N (none when separated) and the band's shear scaled
    // by t_N / sigma_N of the band.
    std::array<double, 3> contact_traction(const InterfaceInput<double>& in) const {
        if (stats.open < 0.5) {
            return traction();
        }
        const double tn = std::min(0.0, in.t_N);
        const double fade = st.y[0] < 0.0 ? std::clamp(tn / st.y[0], 0.0, 1.0) : 0.0;
        return {tn, fade * st.y[3], fade * st.y[4]};
    }
};
template <class M>
DirectResult<M> direct_update(const typename M::Params& mp, const InterfaceSettings& s,
                              const InterfaceState<double, M::n_state>& start,
                              const InterfaceInput<double>& in) {
    DirectResult<M> r;
    r.st = start;
    interface_update<M, double>(mp, s, r.st, in, r.stats);
    return r;
}
template <class M>
DirectResult<M> direct_update(const typename M::Params& mp, const InterfaceSettings& s,
                              const StateVec<double, M::n_state>& y,
                              const InterfaceInput<double>& in) {
    InterfaceState<double, M::n_state> start;
    start.y = y;
    return direct_update<M>(mp, s, start, in);
}

// A Sanisand band at 100 kPa sheared under slowly changing targets: Algorithm 1's rate Newton
// contracts fast (the ordinary lanes beside a hard one in the Newton tests).
inline InterfaceState<double, Sanisand::n_state> ordinary_sanisand_band() {
    InterfaceState<double, Sanisand::n_state> st;
    st.y = sanisand_state(-100.0, 0.5, 0.75);
    return st;
}
inline InterfaceInput<double> ordinary_sanisand_call(double v) {
    return {-100.0 - 2.0 * v, 1.0e-5 * (1.0 + 0.1 * v), 2.0e-6 * (v - 3.0),
            -50.0 - v,        -49.0 + 0.5 * v,          0.0};
}

// One batched Algorithm 1 call (the SIMD path) with lane l's start state and input taken from
// state_of(l) and input_of(l): the state and statistics after it, lane by lane.
template <class M>
struct BatchedResult {
    InterfaceState<simd::batch, M::n_state> st;
    InterfaceStats<simd::batch> stats;
};
template <class M, class StateOf, class InputOf>
BatchedResult<M> batched_update(const typename M::Params& mp, const InterfaceSettings& s,
                                StateOf state_of, InputOf input_of) {
    using Batch = simd::batch;
    auto batch_of = [](auto field) {
        alignas(64) std::array<double, simd::lanes> v;
        for (std::size_t l = 0; l < simd::lanes; ++l) {
            v[l] = field(l);
        }
        return Batch::load_aligned(v.data());
    };
    BatchedResult<M> r;
    for (int k = 0; k < M::n_state; ++k) {
        r.st.y[k] = batch_of([&](std::size_t l) { return state_of(l).y[k]; });
    }
    r.st.eps_n = batch_of([&](std::size_t l) { return state_of(l).eps_n; });
    r.st.eps_p1 = batch_of([&](std::size_t l) { return state_of(l).eps_p1; });
    r.st.eps_p2 = batch_of([&](std::size_t l) { return state_of(l).eps_p2; });
    r.st.gamma1 = batch_of([&](std::size_t l) { return state_of(l).gamma1; });
    r.st.gamma2 = batch_of([&](std::size_t l) { return state_of(l).gamma2; });
    r.st.last_subincrement = batch_of([&](std::size_t l) { return state_of(l).last_subincrement; });
    const InterfaceInput<Batch> in{
        batch_of([&](std::size_t l) { return input_of(l).t_N; }),
        batch_of([&](std::size_t l) { return input_of(l).dg1; }),
        batch_of([&](std::size_t l) { return input_of(l).dg2; }),
        batch_of([&](std::size_t l) { return input_of(l).s_p1; }),
        batch_of([&](std::size_t l) { return input_of(l).s_p2; }),
        batch_of([&](std::size_t l) { return input_of(l).forced_subincrements; })};
    interface_update<M, Batch>(mp, s, r.st, in, r.stats);
    return r;
}

inline bool state_is_finite(const auto& y) {
    return std::all_of(y.begin(), y.end(), [](double v) { return std::isfinite(v); });
}

} // namespace ifsim::test

#ifdef IFSIM_TEST_ENGINE_HELPERS
#include <gtest/gtest.h>

#include <string>

#include "engine/contact_update.hpp"
#include "engine/interface_test_driver.hpp"

namespace ifsim::test {

// --- Jacobian columns of the contact engine (the tolerances are explained in
// test_contact_jacobian.cpp) -----------------------------------------------------------------

struct ColumnErrors {
    double eq37 = 0.0;    // Eq. 37 columns vs central differences, tangential rows
    double central = 0.0; // the engine's central scheme (same inputs) vs central differences
    double normal = 0.0;  // normal row vs k_N n (exact for a penalty)
    bool ok = true;
};

// Two points in one engine call (varied increments and targets, the same tilted frame), each
// compared with its own central differences. With reference = false only the exact penalty row
// is checked (schemes that are not the derivative of the update).
// The points' inputs are given; h is the step of the central differences.
template <class M>
ColumnErrors jacobian_errors(const typename M::Params& mp, const StateVec<double, M::n_state>& y,
                             int ndim, const ContactOptions& opt,
                             const std::vector<PointInput>& inputs, bool reference = true,
                             double h = 1.0e-7) {
    const Frame fr = tilted_frame(ndim);
    // The update the lanes differentiate: an adaptive run's Jacobian lanes solve Algorithm 1 to
    // jacobian_tolerance with the perturbation Newton Jacobian (engine/contact_update.hpp).
    InterfaceSettings ref_s = opt.interface;
    if (ref_s.adaptive && opt.jacobian != ContactJacobian::analytical &&
        ref_s.jacobian_tolerance > 0.0) {
        ref_s.tolerance = ref_s.jacobian_tolerance;
        ref_s.newton_jacobian = NewtonJacobian::perturbation;
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
        cp.input(contact_col::dsp1_dtn)[i] = inputs[i].dsp1_dtn;
        cp.input(contact_col::dsp2_dtn)[i] = inputs[i].dsp2_dtn;
    }
    ContactPoints<M> cp_central = cp;
    ContactEngine<M> engine;
    const ContactReport rep = engine.update(cp, mp, opt);
    ContactOptions central_opt = opt;
    central_opt.jacobian = ContactJacobian::central;
    const bool with_central = reference && opt.jacobian != ContactJacobian::analytical;
    ColumnErrors err;
    err.ok = rep.ok() && (!with_central || engine.update(cp_central, mp, central_opt).ok());
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
            const auto in_p = shifted_input(inputs[i], fr, gp, n_sub);
            const auto in_m = shifted_input(inputs[i], fr, gm, n_sub);
            const auto rp = direct_update<M>(mp, ref_s, y, in_p);
            const auto rm = direct_update<M>(mp, ref_s, y, in_m);
            err.ok = err.ok && rp.stats.status > 0.5 && rm.stats.status > 0.5;
            const auto tp = rp.contact_traction(in_p);
            const auto tm = rm.contact_traction(in_m);
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
                if (with_central) {
                    err.central = std::max(
                        err.central, std::abs(cp_central.jacobian(i, comp, c) - fd[c][comp]) / ref);
                }
            }
        }
    }
    return err;
}

template <class M>
ColumnErrors jacobian_errors(const typename M::Params& mp, const StateVec<double, M::n_state>& y,
                             int ndim, const ContactOptions& opt, bool reference = true) {
    std::vector<PointInput> inputs(2);
    for (int i = 0; i < 2; ++i) {
        inputs[i].dg1 = 1.0e-5 * (1.0 + 0.3 * i);
        inputs[i].dg2 = ndim == 3 ? 4.0e-6 * (1.0 - 0.7 * i) : 0.0;
        inputs[i].t_N = -100.0 - 3.0 * i;
        inputs[i].s_p1 = -52.0 + i;
        inputs[i].s_p2 = -47.0 - i;
    }
    return jacobian_errors<M>(mp, y, ndim, opt, inputs, reference);
}

inline ContactOptions jacobian_options(InterfaceFormulation f, int ndim, bool adaptive) {
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

inline std::string jacobian_label(InterfaceFormulation f, int ndim, bool adaptive) {
    return std::string(f == InterfaceFormulation::novel ? "novel" : "stutz") + " ndim " +
           std::to_string(ndim) + (adaptive ? " adaptive" : " fixed");
}

constexpr double kEq37Tol = 2.0e-2;
constexpr double kCentralTol = 1.0e-3;
constexpr double kNormalTol = 1.0e-9;

template <class M>
void check_all_columns(const typename M::Params& mp, const StateVec<double, M::n_state>& y) {
    for (const auto f : {InterfaceFormulation::novel, InterfaceFormulation::stutz}) {
        for (const int ndim : {2, 3}) {
            for (const bool adaptive : {false, true}) {
                SCOPED_TRACE(jacobian_label(f, ndim, adaptive));
                const auto e = jacobian_errors<M>(mp, y, ndim, jacobian_options(f, ndim, adaptive));
                ASSERT_TRUE(e.ok);
                EXPECT_LT(e.eq37, kEq37Tol);
                EXPECT_LT(e.normal, kNormalTol);
                EXPECT_LT(e.central, kCentralTol);
            }
        }
    }
}

// --- The point-level interface test --------------------------------------------------------

// §5.1: L4C with roughness kappa as interface, the same sand as a continuum (kappa = 1) as the
// sample, both from t_N0 with K0 = 0.5, e0 from D_r0 = 0.88, h mobilised along t1; d_s = 3 mm,
// H = 20 mm; sub-increments of 1e-4 (20x the paper's 5e-6) to keep the fast suite fast.
inline InterfaceTestSpec l4c_spec(InterfaceFormulation f, double kappa = 0.9,
                                  double t_N0 = -100.0) {
    InterfaceTestSpec spec;
    spec.interface_material = l4c(kappa);
    spec.interface_state = as_vector(hypo_state(t_N0));
    spec.sample_material = l4c(1.0);
    spec.sample_state = as_vector(hypo_state(t_N0));
    spec.contact.interface.formulation = f;
    spec.contact.interface.max_subincrement = 1.0e-4;
    return spec;
}

struct DriverRun {
    InterfaceTestResult result;
    std::vector<InterfaceRow> rows;
};
inline DriverRun run_driver(const InterfaceTestSpec& spec) {
    DriverRun r;
    r.result = run_interface_test(spec, [&](const InterfaceRow& row) { r.rows.push_back(row); });
    return r;
}

// Eqs. 25-26 between rows: the step's slip increment over the band thickness at its start.
inline void expect_shear_strain_follows_slip(const std::vector<InterfaceRow>& rows,
                                             double d_s0 = 0.003) {
    for (std::size_t k = 1; k < rows.size(); ++k) {
        const double d_slip = rows[k].slip1 - rows[k - 1].slip1;
        EXPECT_NEAR(rows[k].gamma1 - rows[k - 1].gamma1,
                    std::atan(d_slip / rows[k - 1].band_thickness), 1.0e-12)
            << "step " << rows[k].step;
        EXPECT_NEAR(rows[k].band_thickness, d_s0 * (1.0 + rows[k].eps_n), 1.0e-15);
    }
}

} // namespace ifsim::test
#endif // IFSIM_TEST_ENGINE_HELPERS
