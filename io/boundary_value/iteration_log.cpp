#include "io/boundary_value/iteration_log.hpp"

#include <chrono>
#include <stdexcept>

#include <fmt/format.h>

namespace ifsim::io {

namespace {

double now_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

constexpr const char* header =
    "increment,stage,step,t_begin,t_end,cut_depth,iteration,residual,line_search_steps,"
    "partition_solves,gathers,seconds,element_s,solve_s,contact_s,contact_evaluations,"
    "point_updates,lanes,subincrements,model_evaluations,model_substeps,"
    "interface_newton_iterations,newton_fallbacks,contact_failures,relaxed_reruns,"
    "factorisations,krylov_steps,krylov_fallbacks\n";

} // namespace

IterationLog::IterationLog(const std::filesystem::path& dir, bool append,
                           const fem::StaticSolver& solver)
    : path_(dir / file_name) {
    const bool fresh = !append || !std::filesystem::exists(path_);
    file_ = std::fopen(path_.c_str(), fresh ? "w" : "a");
    if (file_ == nullptr) {
        throw std::runtime_error(fmt::format("cannot write {}", path_.string()));
    }
    if (fresh && std::fputs(header, file_) < 0) {
        throw std::runtime_error(fmt::format("cannot write {}", path_.string()));
    }
    start_ = now_seconds();
    last_ = totals(solver);
}

IterationLog::~IterationLog() {
    if (file_ != nullptr) {
        std::fclose(file_);
    }
}

IterationLog::Totals IterationLog::totals(const fem::StaticSolver& solver) const {
    Totals t;
    t.seconds = now_seconds() - start_;
    const fem::SolverTimers timers = solver.timers();
    t.element = timers.element;
    t.solve = timers.solve;
    t.contact = timers.contact_kernels;
    const fem::ContactSetCounters c = solver.contact_counters();
    t.evaluations = static_cast<double>(c.evaluations);
    t.point_updates = c.point_updates;
    t.lanes = c.lanes;
    t.subincrements = c.subincrements;
    t.model_evaluations = c.constitutive_evaluations;
    t.model_substeps = c.model_substeps;
    t.newton = c.interface_newton_iterations;
    t.fallbacks = c.newton_fallbacks;
    t.failures = static_cast<double>(c.failed_evaluations);
    t.relaxed_reruns = static_cast<double>(c.relaxed_reruns);
    const fem::LinearSolverCounters& lin = solver.counters().linear;
    t.factorisations = static_cast<double>(lin.numeric_factorisations);
    t.krylov_steps = static_cast<double>(lin.krylov_iterations);
    t.krylov_fallbacks = static_cast<double>(lin.krylov_fallbacks);
    return t;
}

void IterationLog::record(long increment, const fem::IncrementInfo& info,
                          const fem::StaticSolver& solver) {
    const Totals t = totals(solver);
    const Totals& l = last_;
    const std::string row = fmt::format(
        "{},{},{},{},{},{},{},{},{},{},{},{:.4f},{:.4f},{:.4f},{:.4f},{},{},{},{},{},{},{},{},{},"
        "{},{},{},{}\n",
        increment, info.stage, info.step, info.t_begin, info.t_end, info.cut_depth,
        info.residuals.size() - 1, info.residuals.back(), info.line_search_steps,
        info.partition_solves, info.gathers, t.seconds - l.seconds, t.element - l.element,
        t.solve - l.solve, t.contact - l.contact, t.evaluations - l.evaluations,
        t.point_updates - l.point_updates, t.lanes - l.lanes, t.subincrements - l.subincrements,
        t.model_evaluations - l.model_evaluations, t.model_substeps - l.model_substeps,
        t.newton - l.newton, t.fallbacks - l.fallbacks, t.failures - l.failures,
        t.relaxed_reruns - l.relaxed_reruns, t.factorisations - l.factorisations,
        t.krylov_steps - l.krylov_steps, t.krylov_fallbacks - l.krylov_fallbacks);
    // Flushed at once: the log is read while a hard increment is still running.
    if (std::fputs(row.c_str(), file_) < 0 || std::fflush(file_) != 0) {
        throw std::runtime_error(fmt::format("cannot write {}", path_.string()));
    }
    last_ = t;
}

} // namespace ifsim::io
