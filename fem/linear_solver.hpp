#pragma once
// Direct sparse solve of the reduced Newton system with SuiteSparse: UMFPACK (default; fill-
// reducing ordering: the better of AMD and METIS) or KLU (AMD; meant for very sparse,
// circuit-like matrices, slower than UMFPACK on 3D meshes).
// The symbolic analysis (fill-reducing ordering) is computed once per matrix pattern and
// reused while the pattern id stays the same; the numeric factorisation runs every call of
// factorise() (the tangent changes every Newton iteration).

#include <cstdint>
#include <memory>
#include <string>

#include <Eigen/SparseCore>

#include "fem/lu_factors.hpp"

namespace ifsim::fem {

enum class LinearSolverKind { umfpack, klu };

struct LinearSolverCounters {
    long symbolic_analyses = 0;
    long numeric_factorisations = 0;
    long solves = 0;
    long krylov_solves = 0;     // solves with a held factorisation as GMRES preconditioner
    long krylov_iterations = 0; // their preconditioner applications
    long krylov_fallbacks = 0;  // of them, unconverged: a new factorisation followed
    // UMFPACK's own report of its numeric factorisations: floating-point operations summed over
    // all of them, and the factors' entries (L + U) and the strategy of the last one (where the
    // solve phase's time goes: fill and flops, not the call count).
    double factor_flops = 0.0;
    double factor_seconds = 0.0;       // wall time in the numeric factorisations
    double krylov_seconds = 0.0;       // wall time in the preconditioned GMRES solves
    double copy_seconds = 0.0;         // of it, copying the factors out (once per factorisation)
    double precondition_seconds = 0.0; // of it, the preconditioner applications
    long factor_nonzeros = 0;
    std::string factor_strategy;
};

class LinearSolver {
public:
    // precondition: the precision of the factors' copy that GMRES's preconditioner solves use.
    explicit LinearSolver(LinearSolverKind kind = LinearSolverKind::umfpack,
                          LuPrecision precondition = LuPrecision::double_precision);
    ~LinearSolver();
    LinearSolver(const LinearSolver&) = delete;
    LinearSolver& operator=(const LinearSolver&) = delete;

    // Factorises A (square, compressed, sorted). Returns false with a reason when the matrix is
    // singular or the library fails; the solver then needs a new factorise() before solve().
    bool factorise(const Eigen::SparseMatrix<double>& A, std::uint64_t pattern_id,
                   std::string& error);
    // x = A^-1 b with the last factorisation (x and b of length n; may not alias).
    bool solve(const double* b, double* x, std::string& error);
    // A factorisation of a matrix with this pattern is held (it may be of older values).
    bool holds_factorisation(std::uint64_t pattern_id) const;
    // x = A^-1 b by GMRES on A (the current values) with the held factorisation as its
    // preconditioner, to ||b - A x|| <= rtol ||b|| within max_iterations preconditioner
    // applications. false: not converged (counted as a fallback; x is then undefined) - the
    // caller factorises A instead.
    bool solve_preconditioned(const Eigen::SparseMatrix<double>& A, const double* b, double* x,
                              double rtol, int max_iterations);

    LinearSolverKind kind() const { return kind_; }
    const LinearSolverCounters& counters() const { return counters_; }

private:
    struct Impl;
    LinearSolverKind kind_;
    LuPrecision precondition_;
    std::unique_ptr<Impl> impl_;
    LinearSolverCounters counters_;
};

} // namespace ifsim::fem
