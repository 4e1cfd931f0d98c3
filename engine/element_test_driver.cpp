#include "engine/element_test_driver.hpp"

#include "engine/point_evaluator.hpp"

#include <chrono>
#include <cmath>
#include <stdexcept>

#include <Eigen/Dense>
#include <fmt/format.h>

namespace ifsim {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

void finish(ElementTestResult& result, const PointCounters& pc, Clock::time_point t_start) {
    result.counters.constitutive_evaluations = pc.constitutive_evaluations;
    result.counters.substeps = pc.substeps;
    result.counters.rejected_substeps = pc.rejected_substeps;
    result.counters.rate_evaluations = pc.rate_evaluations;
    result.constitutive_seconds = pc.seconds;
    result.driver_seconds = seconds_since(t_start) - pc.seconds;
}

// Outcome of one attempted step: converged state or a reason.
template <class M>
struct StepOutcome {
    bool ok = false;
    StateVec<double, M::n_state> y{};
    Sym<double> deps{};
    std::string reason;
    bool unreliable = false;
    bool stalled = false;        // Newton ran out of iterations (not a failed update)
    double first_substeps = 0.0; // substeps of the first evaluation
};

template <class M>
StepOutcome<M> solve_step(PointEvaluator<M>& drv, const ElementTestSettings& settings,
                          const StateVec<double, M::n_state>& y0, const Sym<double>& deps_known,
                          const std::array<bool, 6>& stress_ctl, const Sym<double>& target,
                          Sym<double> guess, ElementTestResult& result,
                          double frozen_substeps = 0.0) {
    StepOutcome<M> out;
    std::vector<int> unknown;
    for (int j = 0; j < 6; ++j) {
        if (stress_ctl[j]) {
            unknown.push_back(j);
        }
    }
    Sym<double> deps = deps_known;
    for (int j : unknown) {
        deps[j] = guess[j];
    }
    for (int it = 0; it <= settings.max_newton_iterations; ++it) {
        const auto ev = drv.evaluate(y0, deps, frozen_substeps);
        if (it == 0) {
            out.first_substeps = ev.substeps;
        }
        if (ev.status < -0.5) {
            out.reason = "the constitutive update failed (non-finite state or runaway substepping)";
            return out;
        }
        if (unknown.empty()) {
            out.ok = true;
            out.y = ev.y;
            out.deps = deps;
            out.unreliable = ev.status < 0.5;
            return out;
        }
        double res_max = 0.0;
        double stress_scale = 1.0;
        Eigen::VectorXd r(static_cast<Eigen::Index>(unknown.size()));
        for (std::size_t k = 0; k < unknown.size(); ++k) {
            r(static_cast<Eigen::Index>(k)) = ev.y[unknown[k]] - target[unknown[k]];
            res_max = std::max(res_max, std::abs(r(static_cast<Eigen::Index>(k))));
        }
        for (int j = 0; j < 6; ++j) {
            stress_scale = std::max(stress_scale, std::abs(ev.y[j]));
        }
        if (res_max <= settings.newton_tolerance * stress_scale) {
            out.ok = true;
            out.y = ev.y;
            out.deps = deps;
            out.unreliable = ev.status < 0.5;
            return out;
        }
        if (it == settings.max_newton_iterations) {
            break;
        }
        ++result.counters.newton_iterations;
        const Eigen::MatrixXd J =
            settings.tangent == TangentKind::perturbation
                ? drv.jacobian(y0, deps, unknown, unknown, ev.substeps, settings.perturbation)
                : drv.rate_jacobian(y0, deps, unknown, unknown);
        const Eigen::FullPivLU<Eigen::MatrixXd> lu(J);
        if (!lu.isInvertible() || !J.allFinite()) {
            out.reason = "singular tangent for the stress-controlled components";
            return out;
        }
        const Eigen::VectorXd dx = lu.solve(-r);
        if (!dx.allFinite()) {
            out.reason = "non-finite Newton correction";
            return out;
        }
        for (std::size_t k = 0; k < unknown.size(); ++k) {
            deps[unknown[k]] += dx(static_cast<Eigen::Index>(k));
        }
    }
    out.reason = fmt::format("the Newton iteration on the stress-controlled components did not "
                             "converge in {} iterations",
                             settings.max_newton_iterations);
    out.stalled = true;
    return out;
}

template <class M>
ElementTestResult
run_typed(const typename M::Params& params, const std::vector<double>& initial,
          const std::vector<ElementStage>& stages, const ElementTestSettings& settings,
          const std::function<void(const ElementRow&)>& on_row, const ElementTestPosition* resume,
          const std::function<void(const ElementTestPosition&)>& on_step) {
    constexpr int N = M::n_state;
    ElementTestResult result;
    const std::vector<double>& start = resume ? resume->state : initial;
    if (static_cast<int>(start.size()) != N) {
        throw std::invalid_argument(fmt::format("{} state of model {} needs {} values, got {}",
                                                resume ? "resumed" : "initial", M::name, N,
                                                start.size()));
    }
    const auto t_start = Clock::now();
    PointCounters pc;
    PointEvaluator<M> drv(params, settings.update, pc);
    StateVec<double, N> y{};
    for (int k = 0; k < N; ++k) {
        y[k] = start[k];
    }
    Sym<double> strain = resume ? resume->strain : Sym<double>{};
    ElementRow row;
    if (!resume) {
        row.state.assign(initial.begin(), initial.end());
        on_row(row);
    }

    // Largest number of halvings of one step before the run gives up.
    constexpr int max_cuts = 6;
    int step = resume ? resume->step : 0;
    ElementTestPosition pos;
    const std::size_t first_stage = resume ? static_cast<std::size_t>(resume->stage) : 0;
    for (std::size_t s = first_stage; s < stages.size(); ++s) {
        const ElementStage& st = stages[s];
        const bool resumed_stage = resume && s == first_stage;
        const Sym<double> stress_start = resumed_stage ? resume->stress_start : stress_of(y);
        Sym<double> guess = resumed_stage ? resume->guess : st.first_guess;
        for (int k = resumed_stage ? resume->step_in_stage + 1 : 1; k <= st.steps; ++k) {
            Sym<double> deps_known{};
            Sym<double> target{};
            for (int j = 0; j < 6; ++j) {
                if (st.stress_controlled[j]) {
                    target[j] = stress_start[j] + st.change[j] * k / st.steps;
                } else {
                    deps_known[j] = st.change[j] / st.steps;
                }
            }
            // Try the whole step; on failure cut it into 2^c equal parts.
            bool done = false;
            std::string reason;
            for (int cut = 0; cut <= max_cuts && !done; ++cut) {
                const int parts = 1 << cut;
                StateVec<double, N> yc = y;
                Sym<double> strain_c = strain;
                Sym<double> guess_c = voigt::scale(guess, 1.0 / parts);
                bool ok = true;
                bool unreliable = false;
                const Sym<double> sig_from = stress_of(y);
                for (int part = 1; part <= parts && ok; ++part) {
                    Sym<double> tgt{};
                    for (int j = 0; j < 6; ++j) {
                        tgt[j] = sig_from[j] + (target[j] - sig_from[j]) * part / parts;
                    }
                    const Sym<double> dk = voigt::scale(deps_known, 1.0 / parts);
                    auto res = solve_step<M>(drv, settings, yc, dk, st.stress_controlled, tgt,
                                             guess_c, result);
                    // Stalled on step noise: the adaptive substeps change with the unknown
                    // strains, so the residual jumps by about the integration tolerance times
                    // the stress change, far above the Newton tolerance in a large step (5 %
                    // axial strain in one step stalled even cut into 64 parts). The same step
                    // with the substeps of its first evaluation frozen is a smooth function of
                    // the strains, as the perturbation tangent already assumes.
                    if (res.stalled && res.first_substeps > 0.0) {
                        ++result.counters.frozen_substep_retries;
                        res = solve_step<M>(drv, settings, yc, dk, st.stress_controlled, tgt,
                                            guess_c, result, res.first_substeps);
                    }
                    if (!res.ok) {
                        ok = false;
                        reason = res.reason;
                        break;
                    }
                    unreliable = unreliable || res.unreliable;
                    yc = res.y;
                    strain_c = voigt::add(strain_c, res.deps);
                    guess_c = res.deps;
                }
                if (ok) {
                    done = true;
                    guess = voigt::sub(strain_c, strain);
                    y = yc;
                    strain = strain_c;
                    if (unreliable) {
                        ++result.counters.unreliable_updates;
                    }
                }
            }
            ++step;
            if (!done) {
                result.ok = false;
                result.reason = fmt::format("step {} (stage {}, step {} of {}): {} (also after "
                                            "cutting the step into {} parts)",
                                            step, s + 1, k, st.steps, reason, 1 << max_cuts);
                finish(result, pc, t_start);
                return result;
            }
            ++result.counters.increments;
            row.step = step;
            row.stage = static_cast<int>(s) + 1;
            row.strain = strain;
            row.state.assign(y.begin(), y.end());
            on_row(row);
            if (on_step) {
                pos = {static_cast<int>(s), k, step, row.state, strain, guess, stress_start};
                on_step(pos);
            }
        }
    }
    finish(result, pc, t_start);
    return result;
}

} // namespace

ElementTestResult run_element_test(const MaterialChoice& material,
                                   const std::vector<double>& initial_state,
                                   const std::vector<ElementStage>& stages,
                                   const ElementTestSettings& settings,
                                   const std::function<void(const ElementRow&)>& on_row,
                                   const ElementTestPosition* resume,
                                   const std::function<void(const ElementTestPosition&)>& on_step) {
    return std::visit(
        [&](const auto& params) {
            using M = typename model_of<std::decay_t<decltype(params)>>::type;
            return run_typed<M>(params, initial_state, stages, settings, on_row, resume, on_step);
        },
        material);
}

} // namespace ifsim
