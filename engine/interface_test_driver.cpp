#include "engine/interface_test_driver.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "engine/interface_points.hpp"
#include "engine/point_evaluator.hpp"

namespace ifsim {
namespace {

using detail::Clock;
using detail::ContinuumInterface;
using detail::CoulombInterface;
using detail::InterfaceResponse;
using detail::seconds_since;

template <class Ms, class Iface>
InterfaceTestResult drive(const InterfaceTestSpec& spec, const typename Ms::Params& sp,
                          Iface& iface, InterfaceTestResult& result,
                          const std::function<void(const InterfaceRow&)>& on_row,
                          const InterfaceTestPosition* resume,
                          const std::function<void(const InterfaceTestPosition&)>& on_step) {
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
    const double t_N0 = ys[0]; // of the initial state, also when resumed
    const double K =
        spec.control == NormalControl::constant_stiffness ? spec.normal_stiffness : 0.0;

    double u_t[2] = {0.0, 0.0};
    double slip[2] = {0.0, 0.0};
    double eps11 = 0.0;             // sample normal strain since the start: u_n = eps11 H
    double guess_g[2] = {0.0, 0.0}; // per full step
    double guess_e11 = 0.0;
    int step = 0;
    if (resume) {
        if (static_cast<int>(resume->sample_state.size()) != NS) {
            throw std::invalid_argument(fmt::format("resumed sample state of model {} needs {} "
                                                    "values, got {}",
                                                    Ms::name, NS, resume->sample_state.size()));
        }
        std::copy(resume->sample_state.begin(), resume->sample_state.end(), ys.begin());
        iface.restore(resume->interface_state);
        for (int a = 0; a < 2; ++a) {
            u_t[a] = resume->u_t[a];
            slip[a] = resume->slip[a];
            guess_g[a] = resume->guess_g[a];
        }
        eps11 = resume->eps11;
        guess_e11 = resume->guess_e11;
        step = resume->step;
    }
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
        iface.fill(row, spec.contact.interface);
        on_row(row);
    };
    if (!resume) {
        emit(0, 0, 0);
    }

    const std::vector<int> rows = {0, 3, 4, 1, 2};
    const std::vector<int> cols = {0, 3, 4};
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
    // Interface model substeps when the current step began, and whether it went past its bound.
    double step_start_substeps = 0.0;
    bool over_budget = false;
    std::string budget_why; // the message of the evaluation that went past the bound
    // The interface point's failure in the last evaluation, if that was why it failed.
    std::optional<FailedContactPoint> point_failure;
    // A frozen discretisation: the sample's substeps and the band's Algorithm 1 sub-increments
    // of a step's first evaluation (0: adaptive).
    struct Frozen {
        double sample_substeps = 0.0;
        double subincrements = 0.0;
    };
    auto evaluate = [&](const double x[3], const double du[2], bool with_jacobian,
                        const Frozen& frozen) {
        Eval e;
        point_failure.reset();
        if (over_budget) {
            e.why = budget_why;
            return e;
        }
        const double t_N = t_N0 - K * H * (eps11 + x[2]);
        e.de = {x[2], 0.0, 0.0, (du[0] - x[0]) / (2.0 * H), (du[1] - x[1]) / (2.0 * H), 0.0};
        e.sample = sample.evaluate(ys, e.de, frozen.sample_substeps);
        if (e.sample.status < -0.5) {
            e.why = "the sample's constitutive update failed";
            return e;
        }
        // Novel: the in-plane interface stresses follow the adjacent continuum (Eqs. 19-20).
        e.iface = iface.evaluate(t_N, x[0], x[1], e.sample.y[1], e.sample.y[2], with_jacobian,
                                 frozen.subincrements);
        const double spent = result.counters.model_substeps - step_start_substeps;
        if (spent > spec.max_step_substeps) {
            over_budget = true;
            budget_why =
                fmt::format("the interface model needed {:.3g} substeps in this step, more "
                            "than the bound of {:.3g} per step ([integration] "
                            "max_step_substeps); smaller steps, or a coarser [integration] "
                            "tolerance, cost less",
                            spent, spec.max_step_substeps);
            e.why = budget_why;
            return e;
        }
        if (!e.iface.ok) {
            point_failure = iface.last_failure();
            e.why = fmt::format("the interface point failed: {}{}",
                                describe_interface_failure(e.iface.cause, e.iface.residual),
                                iface.diagnose(t_N, e.sample.y[1], e.sample.y[2]));
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
        bool stalled = false; // ran out of iterations with every evaluation valid
        // The best iterate of a stalled solve: in the noise the iterates wander, and the one
        // a looser tolerance would have stopped at lies among them.
        double best_residual = std::numeric_limits<double>::infinity();
        double best_x[3] = {0.0, 0.0, 0.0};
        Frozen frozen; // the discretisation this solve ran with
        Frozen first;  // the discretisation of the first evaluation
    };
    auto solve = [&](const double du[2], const double guess[3], const Frozen& frozen) {
        Solve out;
        double x[3] = {guess[0], guess[1], guess[2]};
        Eval cur = evaluate(x, du, false, frozen);
        out.first = {cur.sample.substeps, cur.iface.subincrements};
        out.frozen = frozen;
        for (int it = 0;; ++it) {
            if (!cur.ok) {
                out.why = cur.why;
                return out;
            }
            if (cur.rmax < out.best_residual) {
                out.best_residual = cur.rmax;
                std::copy(x, x + 3, out.best_x);
            }
            if (cur.rmax <= spec.newton_tolerance) {
                out.ok = true;
                std::copy(x, x + 3, out.x);
                out.ys = cur.sample.y;
                out.iterations = it;
                return out;
            }
            if (it == spec.max_newton_iterations) {
                out.stalled = true;
                out.iterations = it;
                out.why = fmt::format("the step's Newton iteration did not converge in {} "
                                      "iterations (relative residual {:.3g})",
                                      spec.max_newton_iterations, cur.rmax);
                return out;
            }
            ++result.counters.newton_iterations;
            if (!cur.iface.has_jacobian) {
                // Another iteration follows: the derivatives at x (the same residual again).
                cur = evaluate(x, du, true, frozen);
                if (!cur.ok) {
                    out.why = cur.why;
                    return out;
                }
            }
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
                trial = evaluate(xt, du, false, frozen);
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
    const std::size_t first_stage = resume ? static_cast<std::size_t>(resume->stage) : 0;
    for (std::size_t s = first_stage; s < spec.stages.size(); ++s) {
        const InterfaceStage& st = spec.stages[s];
        const double du_step[2] = {st.du_t1 / st.steps, st.du_t2 / st.steps};
        const int first_k = resume && s == first_stage ? resume->step_in_stage + 1 : 1;
        for (int k = first_k; k <= st.steps; ++k) {
            ++step;
            step_start_substeps = result.counters.model_substeps;
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
                Solve sol = solve(du, guess, Frozen{});
                Solve first_stalled;
                // Stalled on step noise: the adaptive substeps of the sample and the adaptive
                // sub-increments of the band change with the unknowns, so the residual jumps
                // by about their tolerances, which can exceed the Newton tolerance (a loose
                // Sanisand band under CNS stalled at 1.6e-4 against 1e-4 even cut into 64
                // parts). With the discretisation of the first evaluation frozen the step
                // equations are smooth in the unknowns, as the Jacobian already assumes.
                if (!sol.ok && sol.stalled && !over_budget && sol.first.subincrements > 0.0) {
                    ++result.counters.frozen_retries;
                    first_stalled = sol;
                    sol = solve(du, guess, sol.first);
                }
                // Still stalled: accept the best iterate of the stalled solves when it lies
                // below the noise floor the scene accepts, evaluated again (deterministic) so
                // that the interface's trial state stands at it.
                if (!sol.ok && sol.stalled) {
                    const Solve& best =
                        first_stalled.best_residual < sol.best_residual ? first_stalled : sol;
                    if (best.best_residual <= spec.stagnation_tolerance) {
                        const Eval e = evaluate(best.best_x, du, false, best.frozen);
                        if (e.ok && e.rmax <= spec.stagnation_tolerance) {
                            ++result.counters.stagnation_accepts;
                            const int iterations_done = sol.iterations + first_stalled.iterations;
                            sol = best;
                            sol.ok = true;
                            std::copy(best.best_x, best.best_x + 3, sol.x);
                            sol.ys = e.sample.y;
                            sol.iterations = iterations_done; // both solves' work
                        } else if (!e.ok) {
                            sol.why = e.why; // the re-evaluation's own failure (e.g. the budget)
                        }
                    }
                }
                if (!sol.ok) {
                    why = sol.why;
                    // A stall just above the tolerance is the inner solves' noise, not a wrong
                    // direction: say which settings smooth it (the kappa = 1 Stutz case of
                    // docs/reliability.md stalls at 1.05e-4 against 1e-4).
                    const double stalled_at =
                        std::min(sol.best_residual, first_stalled.best_residual);
                    const double accepted =
                        std::max(spec.newton_tolerance, spec.stagnation_tolerance);
                    if (sol.stalled && sol.first.subincrements > 0.0 &&
                        stalled_at < 10.0 * accepted) {
                        why += fmt::format(
                            "; it stalled at {:.3g}, within 10x of the accepted residual {:.3g}: "
                            "likely the noise of the inner solves (Algorithm 1's stop, the "
                            "models' adaptive substeps), which [integration] polish_iterations = "
                            "2 or a tighter [interface] tolerance smooth, and [integration] "
                            "stagnation_tolerance accepts (docs/reliability.md)",
                            stalled_at, accepted);
                    }
                    if (over_budget || ++cuts > max_cuts) {
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
                result.failed_point = point_failure;
                result.reason =
                    over_budget ? fmt::format("step {} (stage {}, step {} of {}): {}", step, s + 1,
                                              k, st.steps, why)
                                : fmt::format("step {} (stage {}, step {} of {}): {} (also after "
                                              "cutting the step into up to {} parts)",
                                              step, s + 1, k, st.steps, why, 1 << max_cuts);
                break;
            }
            ++result.counters.increments;
            result.counters.step_cuts += cuts;
            emit(step, static_cast<int>(s) + 1, iterations);
            if (on_step) {
                InterfaceTestPosition pos;
                pos.stage = static_cast<int>(s);
                pos.step_in_stage = k;
                pos.step = step;
                pos.sample_state.assign(ys.begin(), ys.end());
                pos.interface_state = iface.committed_state();
                for (int a = 0; a < 2; ++a) {
                    pos.u_t[a] = u_t[a];
                    pos.slip[a] = slip[a];
                    pos.guess_g[a] = guess_g[a];
                }
                pos.eps11 = eps11;
                pos.guess_e11 = guess_e11;
                on_step(pos);
            }
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

InterfaceTestResult
run_interface_test(const InterfaceTestSpec& spec,
                   const std::function<void(const InterfaceRow&)>& on_row,
                   const InterfaceTestPosition* resume,
                   const std::function<void(const InterfaceTestPosition&)>& on_step) {
    InterfaceTestResult result;
    return std::visit(
        [&](const auto& sp) {
            using Ms = typename model_of<std::decay_t<decltype(sp)>>::type;
            if (spec.contact.interface.formulation == InterfaceFormulation::coulomb) {
                CoulombInterface iface(spec.coulomb, spec.sample_state.at(3),
                                       spec.sample_state.at(4), result);
                return drive<Ms>(spec, sp, iface, result, on_row, resume, on_step);
            }
            return std::visit(
                [&](const auto& ip) {
                    using Mi = typename model_of<std::decay_t<decltype(ip)>>::type;
                    ContinuumInterface<Mi> iface(ip, spec.interface_state, spec.contact, result);
                    return drive<Ms>(spec, sp, iface, result, on_row, resume, on_step);
                },
                spec.interface_material);
        },
        spec.sample_material);
}

} // namespace ifsim
