#pragma once
// DIR/iterations.csv of a boundary-value run (`--iteration-log`): one row per residual check of
// the Newton iteration, also in increments that are later cut, with what the solver spent since
// the row before. It answers "where did this increment's time go" for one hard increment
// without a profiler: the wall time, the contact kernels' and the linear solver's share, the
// linear solver's factorisations and GMRES steps, and the interface counters (Algorithm 1 runs,
// sub-increments, model evaluations and substeps, second tries, failed and relaxed updates).
// Columns (docs/scenes.md "Outputs"):
//   increment,stage,step,t_begin,t_end,cut_depth,iteration,residual,line_search_steps,
//   partition_solves,gathers,seconds,element_s,solve_s,contact_s,contact_evaluations,
//   point_updates,lanes,subincrements,model_evaluations,model_substeps,
//   interface_newton_iterations,newton_fallbacks,contact_failures,relaxed_reruns,
//   factorisations,krylov_steps,krylov_fallbacks
// `increment` is the one being solved (the next history row); iteration 0 is the first guess's
// residual. The counters are differences to the previous row, so a column's sum over an
// increment's rows is that increment's cost. A resumed run appends to the file; rows of the
// increment the checkpoint interrupted appear again.

#include <cstdio>
#include <filesystem>

#include "fem/static_solver.hpp"

namespace ifsim::io {

class IterationLog {
public:
    // Opens DIR/iterations.csv (appends when `append` and the file exists). Throws
    // std::runtime_error naming the file when it cannot be written.
    IterationLog(const std::filesystem::path& dir, bool append, const fem::StaticSolver& solver);
    ~IterationLog();
    IterationLog(const IterationLog&) = delete;
    IterationLog& operator=(const IterationLog&) = delete;

    // One row: the iterate `info` has just been checked (its residual is the last entry).
    void record(long increment, const fem::IncrementInfo& info, const fem::StaticSolver& solver);

    static constexpr const char* file_name = "iterations.csv";

private:
    struct Totals {
        double seconds = 0.0, element = 0.0, solve = 0.0, contact = 0.0;
        double evaluations = 0.0, point_updates = 0.0, lanes = 0.0, subincrements = 0.0;
        double model_evaluations = 0.0, model_substeps = 0.0, newton = 0.0, fallbacks = 0.0;
        double failures = 0.0, relaxed_reruns = 0.0;
        double factorisations = 0.0, krylov_steps = 0.0, krylov_fallbacks = 0.0;
    };
    Totals totals(const fem::StaticSolver& solver) const;

    std::filesystem::path path_;
    std::FILE* file_ = nullptr;
    Totals last_;
    double start_ = 0.0; // steady clock, seconds
};

} // namespace ifsim::io
