#include "io/calibrate/calibrate_command.hpp"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <thread>

#include <ceres/ceres.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "io/calibrate/calibration_file.hpp"
#include "io/calibrate/curve_evaluator.hpp"
#include "io/calibrate/measured_curve.hpp"
#include "io/cli/exit_codes.hpp"
#include "io/output/atomic_file.hpp"
#include "io/output/stop_signal.hpp"
#include "io/output/summary_writer.hpp"
#include "io/scene/scene_error.hpp"
#include "io/sweep/mpi_sweep.hpp"
#include "io/sweep/sweep_coordinator.hpp"

namespace ifsim::io {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// The optimiser works on x in [0, 1] per key (p = lower + x (upper - lower)), so that keys of
// very different magnitude (kappa ~ 1, d_s ~ 1e-3 m) take steps of one scale.
std::vector<double> values_of(const CalibrationFile& cal, const double* x) {
    std::vector<double> p(cal.parameters.size());
    for (std::size_t k = 0; k < p.size(); ++k) {
        const FittedParameter& f = cal.parameters[k];
        p[k] = f.lower + x[k] * (f.upper - f.lower);
    }
    return p;
}

// The residuals of one point and, when asked, their forward-difference Jacobian: the point and
// its n perturbed neighbours run as one batch.
class CurveCost final : public ceres::CostFunction {
public:
    CurveCost(CurveEvaluator& evaluator, const CalibrationFile& cal)
        : evaluator_(evaluator), cal_(cal) {
        set_num_residuals(static_cast<int>(evaluator.residual_count()));
        mutable_parameter_block_sizes()->push_back(static_cast<int>(cal.parameters.size()));
    }

    bool Evaluate(double const* const* parameters, double* residuals,
                  double** jacobians) const override {
        const std::size_t n = cal_.parameters.size();
        const double* x = parameters[0];
        const bool jacobian = jacobians != nullptr && jacobians[0] != nullptr;
        std::vector<std::vector<double>> points = {values_of(cal_, x)};
        std::vector<double> steps;
        if (jacobian) {
            for (std::size_t k = 0; k < n; ++k) {
                steps.push_back(x[k] + cal_.step <= 1.0 ? cal_.step : -cal_.step);
                points.push_back(neighbour(x, k, steps[k]));
            }
        }
        auto r = evaluator_.evaluate(points);
        if (!r[0]) {
            return false; // a trial point: Ceres shrinks the step
        }
        const std::size_t m = r[0]->size();
        std::copy(r[0]->begin(), r[0]->end(), residuals);
        if (!jacobian) {
            return true;
        }
        // A neighbour whose run failed is tried on the other side of x (a failed Jacobian at
        // an accepted point would end the fit).
        std::vector<std::vector<double>> retry;
        std::vector<std::size_t> which;
        for (std::size_t k = 0; k < n; ++k) {
            const double other = -steps[k];
            if (!r[k + 1] && x[k] + other >= 0.0 && x[k] + other <= 1.0) {
                steps[k] = other;
                retry.push_back(neighbour(x, k, other));
                which.push_back(k);
            }
        }
        if (!retry.empty()) {
            auto again = evaluator_.evaluate(retry);
            for (std::size_t j = 0; j < which.size(); ++j) {
                r[which[j] + 1] = std::move(again[j]);
            }
        }
        for (std::size_t k = 0; k < n; ++k) {
            if (!r[k + 1]) {
                return false;
            }
            for (std::size_t i = 0; i < m; ++i) {
                jacobians[0][i * n + k] = ((*r[k + 1])[i] - (*r[0])[i]) / steps[k];
            }
        }
        return true;
    }

private:
    std::vector<double> neighbour(const double* x, std::size_t k, double h) const {
        std::vector<double> xk(x, x + cal_.parameters.size());
        xk[k] += h;
        return values_of(cal_, xk.data());
    }

    CurveEvaluator& evaluator_;
    const CalibrationFile& cal_;
};

// A line per Levenberg-Marquardt iteration.
class ProgressLines final : public ceres::IterationCallback {
public:
    ProgressLines(const CalibrationFile& cal, const double* x, bool quiet)
        : cal_(cal), x_(x), quiet_(quiet) {}
    ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
        if (!quiet_) {
            std::string values;
            const std::vector<double> p = values_of(cal_, x_);
            for (std::size_t k = 0; k < p.size(); ++k) {
                values += fmt::format("  {}={:.6g}", cal_.parameters[k].key, p[k]);
            }
            fmt::print(stderr, "ifsim calibrate: iteration {:3}  cost {:.6e}{}{}\n", s.iteration,
                       s.cost, values, s.step_is_successful ? "" : "  (step rejected)");
        }
        return stop_signal() != 0 ? ceres::SOLVER_ABORT : ceres::SOLVER_CONTINUE;
    }

private:
    const CalibrationFile& cal_;
    const double* x_;
    bool quiet_;
};

double rms(const std::vector<double>& a, const std::vector<double>& b) {
    double sum = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        sum += (a[i] - b[i]) * (a[i] - b[i]);
    }
    return a.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(a.size()));
}

std::string fit_csv(const CurvePoints& data, const CurvePoints& fit) {
    std::string text = "path,u_t,t_t_data,t_t_fit,u_n_data,u_n_fit\n";
    for (std::size_t i = 0; i < data.path.size(); ++i) {
        text +=
            fmt::format("{},{},{},{},{},{}\n", data.path[i], data.u_t[i], data.t_t[i], fit.t_t[i],
                        data.u_n.empty() ? "" : fmt::format("{}", data.u_n[i]), fit.u_n[i]);
    }
    return text;
}

std::string evaluations_csv(const CalibrationFile& cal, const std::vector<Evaluation>& evals) {
    std::string text = "evaluation,batch";
    for (const FittedParameter& p : cal.parameters) {
        text += "," + p.key;
    }
    text += ",id,status,cost,reused,reason\n";
    for (std::size_t i = 0; i < evals.size(); ++i) {
        const Evaluation& e = evals[i];
        text += fmt::format("{},{}", i + 1, e.batch);
        for (const double v : e.values) {
            text += fmt::format(",{}", v);
        }
        std::string reason = e.reason;
        std::replace(reason.begin(), reason.end(), ',', ';');
        std::replace(reason.begin(), reason.end(), '\n', ' ');
        text += fmt::format(",{},{},{},{},{}\n", e.id, e.ok ? "ok" : "failed",
                            e.ok ? fmt::format("{}", e.cost) : "", e.reused ? 1 : 0, reason);
    }
    return text;
}

int calibrate(const CalibrateOptions& opt, const SweepLayout& layout, RemoteWorkers* remote) {
    const auto t0 = Clock::now();
    CalibrationFile cal;
    CurvePoints data;
    try {
        cal = read_calibration_file(opt.file);
        data = read_measured_curve(cal.data_path, cal.column_u_t, cal.column_t_t, cal.column_u_n);
    } catch (const std::exception& e) {
        fmt::print(stderr, "ifsim calibrate: error: {}\n", e.what());
        return exit_code::bad_input;
    }
    const fs::path out = opt.runs.out;
    try {
        fs::create_directories(out / "runs");
        std::error_code ignored;
        fs::remove(out / "calibration.json", ignored); // never left to pass for this fit's
    } catch (const std::exception& e) {
        fmt::print(stderr, "ifsim calibrate: error: cannot write {}: {}\n", out.string(), e.what());
        return exit_code::io_error;
    }
    const std::size_t n = cal.parameters.size();
    if (!opt.runs.quiet) {
        fmt::print(stderr,
                   "ifsim calibrate: {} key(s) to {} data points of {}{}; {} run(s) at a time "
                   "with {} thread(s) each\n",
                   n, data.t_t.size(), cal.data_path.string(),
                   data.u_n.empty() || cal.weight_u_n == 0.0 ? " (t_t)" : " (t_t and u_n)",
                   layout.local_jobs + (remote ? remote->slots() : 0), layout.threads);
    }
    CurveEvaluator evaluator(cal, data, opt.runs, layout, remote);
    std::vector<double> x(n);
    for (std::size_t k = 0; k < n; ++k) {
        const FittedParameter& f = cal.parameters[k];
        x[k] = (f.initial - f.lower) / (f.upper - f.lower);
    }
    ceres::Problem problem;
    problem.AddResidualBlock(new CurveCost(evaluator, cal), nullptr, x.data());
    for (std::size_t k = 0; k < n; ++k) {
        problem.SetParameterLowerBound(x.data(), static_cast<int>(k), 0.0);
        problem.SetParameterUpperBound(x.data(), static_cast<int>(k), 1.0);
    }
    ceres::Solver::Options options;
    options.minimizer_type = ceres::TRUST_REGION;
    options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
    options.linear_solver_type = ceres::DENSE_QR;
    options.max_num_iterations = cal.max_iterations;
    // The runs are smooth in the keys only to their own tolerances (adaptive sub-increments
    // give cost noise of ~1e-3 relative): tighter stops only collect rejected steps.
    options.function_tolerance = 1e-8;
    options.gradient_tolerance = 1e-12;
    options.parameter_tolerance = 1e-6;
    options.num_threads = 1; // the runs use the cores
    options.logging_type = ceres::SILENT;
    options.update_state_every_iteration = true;
    ProgressLines lines(cal, x.data(), opt.runs.quiet);
    options.callbacks.push_back(&lines);
    ceres::Solver::Summary summary;
    const StopSignals signals;
    ceres::Solve(options, &problem, &summary);
    const int stopped = evaluator.interrupted() != 0 ? evaluator.interrupted() : stop_signal();
    const bool failed = stopped == 0 && summary.termination_type == ceres::FAILURE;
    const std::vector<Evaluation>& evals = evaluator.evaluations();
    if (failed && (evals.empty() || !evals.front().ok)) {
        // The start itself could not be evaluated: nothing was fitted.
        const std::string why =
            evals.empty()
                ? summary.message
                : fmt::format("the run at the initial values ({}) failed: {}",
                              (out / "runs" / evals.front().id).string(), evals.front().reason);
        fmt::print(stderr, "ifsim calibrate: error: {}\n", why);
        try {
            write_file_atomically(out / "evaluations.csv", evaluations_csv(cal, evals));
        } catch (const std::exception&) {
        }
        return exit_code::run_failed;
    }
    const std::vector<double> fitted = values_of(cal, x.data());
    nlohmann::ordered_json j;
    j["calibration"] = opt.file;
    // failed: Ceres stopped on an evaluation it could not do (a Jacobian whose runs failed on
    // both sides); the values are the last accepted point's.
    j["status"] = stopped != 0 ? "interrupted" : failed ? "failed" : "ok";
    j["converged"] = summary.termination_type == ceres::CONVERGENCE;
    j["termination"] = summary.message;
    j["iterations"] = summary.iterations.empty() ? 0 : summary.iterations.back().iteration;
    j["evaluations"] = evaluator.evaluations().size();
    std::size_t reused = 0;
    for (const Evaluation& e : evaluator.evaluations()) {
        reused += e.reused;
    }
    j["reused_runs"] = reused;
    j["initial_cost"] = summary.initial_cost;
    j["final_cost"] = summary.final_cost;
    nlohmann::ordered_json params = nlohmann::ordered_json::array();
    for (std::size_t k = 0; k < n; ++k) {
        const FittedParameter& f = cal.parameters[k];
        params.push_back({{"key", f.key},
                          {"fitted", fitted[k]},
                          {"initial", f.initial},
                          {"lower", f.lower},
                          {"upper", f.upper},
                          {"at_bound", x[k] <= 1e-9 || x[k] >= 1.0 - 1e-9}});
    }
    j["parameters"] = params;
    // The fitted point's run: the last accepted point, evaluated when it was accepted.
    const fs::path best = evaluator.run_dir(fitted);
    std::string csv;
    const std::optional<RunRecord> best_record = read_run_record(best);
    if (best_record && best_record->ok) {
        const CurvePoints fit = run_at_data_points(data, read_run_curve(best / "history.csv"));
        j["rms_t_t"] = rms(fit.t_t, data.t_t);
        if (!data.u_n.empty()) {
            j["rms_u_n"] = rms(fit.u_n, data.u_n);
        }
        j["run"] = fs::relative(best, out).string();
        csv = fit_csv(data, fit);
    } else {
        j["run"] = nullptr; // interrupted before the start's run ended
    }
    j["data"] = cal.data_path.string();
    j["data_points"] = data.t_t.size();
    j["weight_u_n"] = cal.weight_u_n;
    j["step"] = cal.step;
    j["scales"] = {{"t_t", evaluator.scales().t_t}, {"u_n", evaluator.scales().u_n}};
    j["fixed"] = cal.fixed;
    j["wall_s"] = std::chrono::duration<double>(Clock::now() - t0).count();
    j["revision"] = build_revision();
    j["solver"] = "Ceres Solver " + std::string(CERES_VERSION_STRING) +
                  ", Levenberg-Marquardt, forward-difference Jacobian";
    try {
        if (!csv.empty()) {
            write_file_atomically(out / "fit.csv", csv);
        }
        write_file_atomically(out / "evaluations.csv",
                              evaluations_csv(cal, evaluator.evaluations()));
        write_file_atomically(out / "calibration.json", j.dump(2) + "\n");
    } catch (const std::exception& e) {
        fmt::print(stderr, "ifsim calibrate: error: {}\n", e.what());
        return exit_code::io_error;
    }
    if (stopped != 0) {
        fmt::print(stderr,
                   "ifsim calibrate: interrupted by {}; calibration.json holds the last "
                   "accepted point (the same command goes on, reusing every run)\n",
                   signal_name(stopped));
        return interrupted_exit_code(stopped);
    }
    if (failed) {
        fmt::print(stderr,
                   "ifsim calibrate: stopped: {}; calibration.json holds the last "
                   "accepted point\n",
                   summary.message);
        return exit_code::run_failed;
    }
    if (!opt.runs.quiet) {
        std::string values;
        for (std::size_t k = 0; k < n; ++k) {
            values += fmt::format(" {}={:.6g}", cal.parameters[k].key, fitted[k]);
        }
        fmt::print("ifsim calibrate: {}{} after {} iterations ({} runs); rms t_t {:.4g} kPa; "
                   "{}\n",
                   j["converged"].get<bool>() ? "converged:" : "NOT converged:", values,
                   j["iterations"].get<int>(), evaluator.evaluations().size(),
                   j.value("rms_t_t", std::nan("")), (out / "calibration.json").string());
    }
    return exit_code::ok;
}

} // namespace

int calibrate_command(const CalibrateOptions& opt) {
    if (launched_by_mpi()) {
        return run_on_mpi_ranks(opt.runs, [&](const SweepLayout& layout, RemoteWorkers& workers) {
            return calibrate(opt, layout, &workers);
        });
    }
    // Local: a batch holds the point and its n neighbours, so n + 1 runs at a time. The number
    // of keys is known once the file is read; a bad file is reported by calibrate().
    std::size_t keys = 1;
    try {
        keys = read_calibration_file(opt.file).parameters.size();
    } catch (const std::exception&) {
    }
    return calibrate(opt, local_layout(keys + 1, opt.runs), nullptr);
}

} // namespace ifsim::io
