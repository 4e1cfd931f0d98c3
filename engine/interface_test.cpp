#include "engine/interface_test.hpp"

#include <array>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "engine/point_evaluator.hpp"

namespace ifsim {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

// What the driver needs of the interface point after an evaluation.
struct InterfaceResponse {
    bool ok = true;
    double cause = 0.0; // interface_failure code when !ok
    double tau[2] = {0.0, 0.0};
    double dtau_dg[2][2] = {{0.0, 0.0}, {0.0, 0.0}}; // d tau_a / d dg_T,b
    double dtau_dtN[2] = {0.0, 0.0};
    double dtau_dsp[2][2] = {{0.0, 0.0}, {0.0, 0.0}}; // d tau_a / d s_p(b+1), novel only
    double residual = 0.0;
};

// A continuum model used as interface model through Algorithm 1 and the contact engine.
template <class Mi>
class ContinuumInterface {
public:
    static constexpr int NS = Mi::n_state;
    ContinuumInterface(const typename Mi::Params& p, const std::vector<double>& y0,
                       const ContactOptions& opt, InterfaceTestResult& res)
        : params_(p), opt_(opt), res_(res), points_(1, 3) {
        if (static_cast<int>(y0.size()) != NS) {
            throw std::invalid_argument(fmt::format(
                "interface state of model {} needs {} values, got {}", Mi::name, NS, y0.size()));
        }
        StateVec<double, NS> y{};
        std::copy(y0.begin(), y0.end(), y.begin());
        points_.set_state(0, y);
        const double n[3] = {1, 0, 0}, t1[3] = {0, 1, 0}, t2[3] = {0, 0, 1};
        points_.set_frame(0, n, t1, t2);
        // t_N is prescribed by the driver, not a penalty: k_N = 1 makes the slave's normal
        // perturbation lane the derivative with respect to t_N itself.
        points_.input(contact_col::k_N)[0] = 1.0;
    }

    InterfaceResponse evaluate(double t_N, double dg1, double dg2, double s_p1, double s_p2) {
        InterfaceResponse r;
        if (opt_.interface.formulation == InterfaceFormulation::novel) {
            // The novel formulation's traction also depends on the extrapolated continuum
            // stress (Eqs. 19-20), which the Eq. 37 lanes do not perturb. At point level the
            // sample is that continuum, so the driver's Newton needs d tau / d s_p too: two
            // single-lane probes (run first; the base evaluation below leaves the trial state).
            probe_opt_ = opt_;
            probe_opt_.jacobian = ContactJacobian::analytical;
            const double sp[2] = {s_p1, s_p2};
            for (int b = 0; b < 2; ++b) {
                const double h = 1.0e-6 * std::max(std::abs(sp[b]), 1.0);
                double q[2] = {sp[0], sp[1]};
                q[b] += h;
                const auto plus = probe(t_N, dg1, dg2, q[0], q[1]);
                q[b] -= 2.0 * h;
                const auto minus = probe(t_N, dg1, dg2, q[0], q[1]);
                for (int a = 0; a < 2; ++a) {
                    r.dtau_dsp[a][b] = (plus[a] - minus[a]) / (2.0 * h);
                }
            }
        }
        points_.input(contact_col::t_N)[0] = t_N;
        points_.input(contact_col::dg1)[0] = dg1;
        points_.input(contact_col::dg2)[0] = dg2;
        points_.input(contact_col::s_p1)[0] = s_p1;
        points_.input(contact_col::s_p2)[0] = s_p2;
        const auto t0 = Clock::now();
        const ContactReport rep = engine_.update(points_, params_, opt_);
        res_.interface_seconds += seconds_since(t0);
        res_.counters.interface_evaluations += rep.constitutive_evaluations;
        res_.counters.constitutive_evaluations += rep.constitutive_evaluations;
        res_.counters.model_substeps += rep.model_substeps;
        last_subincrements_ = rep.subincrements;
        last_newton_ = rep.newton_iterations;
        r.ok = rep.ok();
        r.cause = rep.first_failed_cause;
        last_band_clamped_ = rep.band_clamped > 0;
        r.residual = points_.output(contact_col::residual)[0];
        r.tau[0] = points_.output(contact_col::traction + 1)[0];
        r.tau[1] = points_.output(contact_col::traction + 2)[0];
        // Columns: slave e_1 (normal: d/d t_N with k_N = 1), master e_2, e_3 (+dg_T1, +dg_T2).
        for (int a = 0; a < 2; ++a) {
            r.dtau_dtN[a] = points_.jacobian(0, 1 + a, 0);
            for (int b = 0; b < 2; ++b) {
                r.dtau_dg[a][b] = points_.jacobian(0, 1 + a, 3 + 1 + b);
            }
        }
        return r;
    }

    void commit(InterfaceTestResult& res) {
        points_.commit();
        res.counters.band_clamped_steps += last_band_clamped_ ? 1 : 0;
        res.counters.subincrements += last_subincrements_;
        res.counters.interface_newton_iterations += last_newton_;
    }

    void fill(InterfaceRow& row, double d_s0) const {
        const double* y[NS];
        for (int k = 0; k < NS; ++k) {
            y[k] = points_.committed(k);
        }
        row.s_n = y[0][0];
        row.s_p1 = y[1][0];
        row.s_p2 = y[2][0];
        row.e_interface = y[6][0];
        row.eps_n = points_.committed(NS + contact_state::eps_n)[0];
        row.eps_p1 = points_.committed(NS + contact_state::eps_p1)[0];
        row.eps_p2 = points_.committed(NS + contact_state::eps_p2)[0];
        row.gamma1 = points_.committed(NS + contact_state::gamma1)[0];
        row.gamma2 = points_.committed(NS + contact_state::gamma2)[0];
        row.band_thickness = d_s0 * (1.0 + row.eps_n);
    }

private:
    std::array<double, 2> probe(double t_N, double dg1, double dg2, double s_p1, double s_p2) {
        points_.input(contact_col::t_N)[0] = t_N;
        points_.input(contact_col::dg1)[0] = dg1;
        points_.input(contact_col::dg2)[0] = dg2;
        points_.input(contact_col::s_p1)[0] = s_p1;
        points_.input(contact_col::s_p2)[0] = s_p2;
        const auto t0 = Clock::now();
        const ContactReport rep = probe_engine_.update(points_, params_, probe_opt_);
        res_.interface_seconds += seconds_since(t0);
        res_.counters.interface_evaluations += rep.constitutive_evaluations;
        res_.counters.constitutive_evaluations += rep.constitutive_evaluations;
        return {points_.output(contact_col::traction + 1)[0],
                points_.output(contact_col::traction + 2)[0]};
    }

    const typename Mi::Params& params_;
    const ContactOptions& opt_;
    ContactOptions probe_opt_;
    ContactEngine<Mi> probe_engine_;
    InterfaceTestResult& res_;
    ContactPoints<Mi> points_;
    ContactEngine<Mi> engine_;
    double last_subincrements_ = 0.0;
    bool last_band_clamped_ = false;
    double last_newton_ = 0.0;
};

// Coulomb penalty friction: exact return mapping with its analytical derivatives.
class CoulombInterface {
public:
    CoulombInterface(const CoulombParams& p, double tau1, double tau2) : p_(p) {
        tau_[0] = tau1;
        tau_[1] = tau2;
    }
    CoulombInterface(const CoulombParams& p, double tau1, double tau2, InterfaceTestResult& res)
        : CoulombInterface(p, tau1, tau2) {
        res_ = &res;
    }
    InterfaceResponse evaluate(double t_N, double dg1, double dg2, double, double) {
        const auto t0 = Clock::now();
        const auto c = coulomb_update<double>(p_, t_N, tau_[0], tau_[1], dg1, dg2);
        if (res_) {
            res_->interface_seconds += seconds_since(t0);
            res_->counters.interface_evaluations += 1.0;
            res_->counters.constitutive_evaluations += 1.0;
        }
        InterfaceResponse r;
        r.tau[0] = trial_[0] = c.tau1;
        r.tau[1] = trial_[1] = c.tau2;
        for (int a = 0; a < 2; ++a) {
            r.dtau_dtN[a] = c.dtau_dtN[a];
            for (int b = 0; b < 2; ++b) {
                r.dtau_dg[a][b] = c.dtau_ddg[a][b];
            }
        }
        return r;
    }
    void commit(InterfaceTestResult&) {
        tau_[0] = trial_[0];
        tau_[1] = trial_[1];
    }
    void fill(InterfaceRow& row, double) const {
        row.s_n = row.t_n;
        row.band_thickness = 0.0;
    }

private:
    CoulombParams p_;
    InterfaceTestResult* res_ = nullptr;
    double tau_[2] = {0.0, 0.0};
    double trial_[2] = {0.0, 0.0};
};

template <class Ms, class Iface>
InterfaceTestResult drive(const InterfaceTestSpec& spec, const typename Ms::Params& sp,
                          Iface& iface, InterfaceTestResult& result,
                          const std::function<void(const InterfaceRow&)>& on_row) {
    constexpr int NS = Ms::n_state;
    if (static_cast<int>(spec.sample_state.size()) != NS) {
        throw std::invalid_argument(fmt::format("sample state of model {} needs {} values, got {}",
                                                Ms::name, NS, spec.sample_state.size()));
    }
    const auto t_start = Clock::now();
    PointCounters pc;
    PointEvaluator<Ms> sample(sp, spec.sample_update, pc);
    StateVec<double, NS> ys{};
    std::copy(spec.sample_state.begin(), spec.sample_state.end(), ys.begin());
    const double H = spec.height;
    const double t_N0 = ys[0];
    const double K =
        spec.control == NormalControl::constant_stiffness ? spec.normal_stiffness : 0.0;
    const double d_s0 = spec.contact.interface.shear_band_thickness;

    double u_t[2] = {0.0, 0.0};
    double slip[2] = {0.0, 0.0};
    double eps11 = 0.0; // sample normal strain since the start: u_n = eps11 H
    InterfaceRow row;
    auto emit = [&](int step, int stage, int iterations) {
        row.step = step;
        row.stage = stage;
        row.u_t1 = u_t[0];
        row.u_t2 = u_t[1];
        row.u_n = eps11 * H;
        row.t_n = t_N0 - K * H * eps11; // the prescribed normal contact stress
        row.t_t1 = ys[3];
        row.t_t2 = ys[4];
        row.sample_s11 = ys[0];
        row.sample_s22 = ys[1];
        row.sample_s33 = ys[2];
        row.sample_s12 = ys[3];
        row.sample_s13 = ys[4];
        row.e_sample = ys[6];
        row.slip1 = slip[0];
        row.slip2 = slip[1];
        row.newton_iterations = iterations;
        iface.fill(row, d_s0);
        on_row(row);
    };
    emit(0, 0, 0);

    const std::vector<int> rows = {0, 3, 4, 1, 2};
    const std::vector<int> cols = {0, 3, 4};
    double guess_g[2] = {0.0, 0.0}; // per full step
    double guess_e11 = 0.0;
    int step = 0;
    // One evaluation of the step equations at the unknowns x = (dg_T1, dg_T2, deps_11) for the
    // plate displacement increment du (this leaves the interface's trial state at x).
    struct Eval {
        bool ok = false;
        std::string why;
        double R[3] = {0.0, 0.0, 0.0};
        double rmax = 0.0;
        Sym<double> de{};
        typename PointEvaluator<Ms>::Eval sample;
        InterfaceResponse iface;
    };
    auto evaluate = [&](const double x[3], const double du[2]) {
        Eval e;
        const double t_N = t_N0 - K * H * (eps11 + x[2]);
        e.de = {x[2], 0.0, 0.0, (du[0] - x[0]) / (2.0 * H), (du[1] - x[1]) / (2.0 * H), 0.0};
        e.sample = sample.evaluate(ys, e.de);
        if (e.sample.status < -0.5) {
            e.why = "the sample's constitutive update failed";
            return e;
        }
        // Novel: the in-plane interface stresses follow the adjacent continuum (Eqs. 19-20).
        e.iface = iface.evaluate(t_N, x[0], x[1], e.sample.y[1], e.sample.y[2]);
        if (!e.iface.ok) {
            e.why = fmt::format("the interface point failed: {} (Algorithm 1 residual {:.3g})",
                                interface_failure::describe(e.iface.cause), e.iface.residual);
            return e;
        }
        e.R[0] = e.iface.tau[0] - e.sample.y[3];
        e.R[1] = e.iface.tau[1] - e.sample.y[4];
        e.R[2] = e.sample.y[0] - t_N;
        e.rmax = std::max({std::abs(e.R[0]), std::abs(e.R[1]), std::abs(e.R[2])}) /
                 std::max(std::abs(t_N), 1.0);
        e.ok = true;
        return e;
    };
    // d R / d x at an evaluation: interface Jacobian (Eq. 37 lanes and, for the novel
    // formulation, d tau / d s_p) and the sample's tangent by perturbation.
    auto jacobian = [&](const Eval& e) {
        const Eigen::MatrixXd Call =
            sample.jacobian(ys, e.de, rows, cols, e.sample.substeps, 1.0e-7);
        const Eigen::MatrixXd C = Call.topRows(3);     // rows 11, 12, 13
        const Eigen::MatrixXd Cp = Call.bottomRows(2); // rows 22, 33
        const double dtN = -K * H;
        const InterfaceResponse& ir = e.iface;
        Eigen::Matrix3d J;
        for (int a = 0; a < 2; ++a) {
            for (int b = 0; b < 2; ++b) {
                J(a, b) = ir.dtau_dg[a][b] + C(1 + a, 1 + b) / (2.0 * H) -
                          (ir.dtau_dsp[a][0] * Cp(0, 1 + b) + ir.dtau_dsp[a][1] * Cp(1, 1 + b)) /
                              (2.0 * H);
            }
            J(a, 2) = ir.dtau_dtN[a] * dtN - C(1 + a, 0) + ir.dtau_dsp[a][0] * Cp(0, 0) +
                      ir.dtau_dsp[a][1] * Cp(1, 0);
            J(2, a) = -C(0, 1 + a) / (2.0 * H);
        }
        J(2, 2) = C(0, 0) - dtN;
        return J;
    };
    // Newton on x for one plate displacement increment, with a backtracking line search (the
    // step equations have near-singular points at the peak, where sample and interface soften
    // in series). On success the interface's trial state is at the solution.
    struct Solve {
        bool ok = false;
        std::string why;
        double x[3] = {0.0, 0.0, 0.0};
        StateVec<double, NS> ys{};
        int iterations = 0;
    };
    auto solve = [&](const double du[2], const double guess[3]) {
        Solve out;
        double x[3] = {guess[0], guess[1], guess[2]};
        Eval cur = evaluate(x, du);
        for (int it = 0;; ++it) {
            if (!cur.ok) {
                out.why = cur.why;
                return out;
            }
            if (cur.rmax <= spec.newton_tolerance) {
                out.ok = true;
                std::copy(x, x + 3, out.x);
                out.ys = cur.sample.y;
                out.iterations = it;
                return out;
            }
            if (it == spec.max_newton_iterations) {
                out.why = fmt::format("the step's Newton iteration did not converge in {} "
                                      "iterations (relative residual {:.3g})",
                                      spec.max_newton_iterations, cur.rmax);
                return out;
            }
            ++result.counters.newton_iterations;
            const Eigen::Vector3d dx =
                jacobian(cur).fullPivLu().solve(-Eigen::Vector3d(cur.R[0], cur.R[1], cur.R[2]));
            if (!dx.allFinite()) {
                out.why = "singular step Jacobian";
                return out;
            }
            double alpha = 1.0;
            double xt[3];
            Eval trial;
            for (int ls = 0; ls < 4; ++ls, alpha *= 0.5) {
                for (int c = 0; c < 3; ++c) {
                    xt[c] = x[c] + alpha * dx(c);
                }
                trial = evaluate(xt, du);
                if (trial.ok && trial.rmax < cur.rmax) {
                    break;
                }
            }
            std::copy(xt, xt + 3, x);
            cur = trial;
        }
    };

    // Largest number of halvings of a step before the run gives up.
    constexpr int max_cuts = 6;
    for (std::size_t s = 0; s < spec.stages.size(); ++s) {
        const InterfaceStage& st = spec.stages[s];
        const double du_step[2] = {st.du_t1 / st.steps, st.du_t2 / st.steps};
        for (int k = 1; k <= st.steps; ++k) {
            ++step;
            // Take the step whole if possible; on failure halve the rest, committing every
            // sub-step that converged (each is a valid increment of the test).
            double done = 0.0;
            double fraction = 1.0;
            int cuts = 0;
            int iterations = 0;
            std::string why;
            while (done < 1.0 - 1.0e-12) {
                const double f = std::min(fraction, 1.0 - done);
                const double du[2] = {du_step[0] * f, du_step[1] * f};
                const double guess[3] = {guess_g[0] * f, guess_g[1] * f, guess_e11 * f};
                const Solve sol = solve(du, guess);
                if (!sol.ok) {
                    why = sol.why;
                    if (++cuts > max_cuts) {
                        break;
                    }
                    fraction = 0.5 * f;
                    continue;
                }
                iface.commit(result);
                ys = sol.ys;
                eps11 += sol.x[2];
                for (int a = 0; a < 2; ++a) {
                    u_t[a] += du[a];
                    slip[a] += sol.x[a];
                    guess_g[a] = sol.x[a] / f;
                }
                guess_e11 = sol.x[2] / f;
                iterations += sol.iterations;
                done += f;
            }
            if (done < 1.0 - 1.0e-12) {
                result.ok = false;
                result.reason = fmt::format("step {} (stage {}, step {} of {}): {} (also after "
                                            "cutting the step into up to {} parts)",
                                            step, s + 1, k, st.steps, why, 1 << max_cuts);
                break;
            }
            ++result.counters.increments;
            result.counters.step_cuts += cuts;
            emit(step, static_cast<int>(s) + 1, iterations);
        }
        if (!result.ok) {
            break;
        }
    }
    result.counters.sample_evaluations = static_cast<double>(pc.constitutive_evaluations);
    result.counters.constitutive_evaluations += result.counters.sample_evaluations;
    result.sample_seconds = pc.seconds;
    result.driver_seconds =
        seconds_since(t_start) - result.sample_seconds - result.interface_seconds;
    return result;
}

} // namespace

InterfaceTestResult run_interface_test(const InterfaceTestSpec& spec,
                                       const std::function<void(const InterfaceRow&)>& on_row) {
    InterfaceTestResult result;
    return std::visit(
        [&](const auto& sp) {
            using Ms = typename model_of<std::decay_t<decltype(sp)>>::type;
            if (spec.kind == InterfaceKind::coulomb) {
                CoulombInterface iface(spec.coulomb, spec.sample_state.at(3),
                                       spec.sample_state.at(4), result);
                return drive<Ms>(spec, sp, iface, result, on_row);
            }
            return std::visit(
                [&](const auto& ip) {
                    using Mi = typename model_of<std::decay_t<decltype(ip)>>::type;
                    ContinuumInterface<Mi> iface(ip, spec.interface_state, spec.contact, result);
                    return drive<Ms>(spec, sp, iface, result, on_row);
                },
                spec.interface_material);
        },
        spec.sample_material);
}

} // namespace ifsim
