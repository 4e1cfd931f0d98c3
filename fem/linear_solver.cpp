#include "fem/linear_solver.hpp"

#include "fem/blas_binding.hpp"
#include "fem/blocked_product.hpp"
#include "fem/krylov_gmres.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include <Eigen/Dense>
#include <fmt/format.h>
#include <suitesparse/klu.h>
#include <suitesparse/umfpack.h>

namespace ifsim::fem {
namespace {

// Below this estimate of the reciprocal condition number (smallest over largest pivot
// magnitude) the matrix is numerically singular: an unsupported body gives ~1e-16, a sound
// soil model ~0.1-1, stiff structures next to soft soil ~1e-6..1e-9.
constexpr double singular_rcond = 1.0e-13;

// Adds the wall time of its scope to `seconds` (every return path of a lambda counted).
class ScopedSeconds {
public:
    explicit ScopedSeconds(double& seconds)
        : seconds_(seconds), from_(std::chrono::steady_clock::now()) {}
    ~ScopedSeconds() {
        seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - from_).count();
    }
    ScopedSeconds(const ScopedSeconds&) = delete;
    ScopedSeconds& operator=(const ScopedSeconds&) = delete;

private:
    double& seconds_;
    std::chrono::steady_clock::time_point from_;
};

} // namespace

struct LinearSolver::Impl {
    // The arrays of the factorised matrix (UMFPACK's solve reads them again).
    const Eigen::SparseMatrix<double>* A = nullptr;
    int n = 0;
    std::uint64_t analysed_pattern = 0; // 0: no symbolic analysis held
    bool factorised = false;

    double control[UMFPACK_CONTROL];
    double control_plain[UMFPACK_CONTROL]; // no iterative refinement: a preconditioner
    double info[UMFPACK_INFO];
    void* umf_symbolic = nullptr;
    void* umf_numeric = nullptr;
    // UMFPACK's factors copied out for GMRES's preconditioner solves, on the first such solve
    // after a factorisation (a held factorisation used only for its direct solve is not copied),
    // in the settings' precision (docs/performance.md, "Preconditioner solves").
    LuFactors lu;
    bool lu_tried = false;

    klu_common common;
    klu_symbolic* klu_sym = nullptr;
    klu_numeric* klu_num = nullptr;
    std::vector<double> rhs; // KLU solves in place
    BlockedProduct product;  // GMRES's products with the current tangent

    Impl() {
        configure_blas();
        umfpack_di_defaults(control);
        // AMD/COLAMD and METIS both tried, the ordering with less fill kept: on 3D hex meshes
        // METIS needs ~2.4x fewer flops per factorisation than the default AMD (measured on a
        // 16x8x16 block); the extra analysis cost is paid once per pattern.
        control[UMFPACK_ORDERING] = UMFPACK_ORDERING_CHOLMOD;
        std::copy(control, control + UMFPACK_CONTROL, control_plain);
        control_plain[UMFPACK_IRSTEP] = 0; // refinement would use the current matrix's values
        klu_defaults(&common);
    }
    ~Impl() { release(); }
    void release_numeric() {
        if (umf_numeric) {
            umfpack_di_free_numeric(&umf_numeric);
        }
        lu.clear();
        lu_tried = false;
        if (klu_num) {
            klu_free_numeric(&klu_num, &common);
        }
        factorised = false;
    }
    void release() {
        release_numeric();
        if (umf_symbolic) {
            umfpack_di_free_symbolic(&umf_symbolic);
        }
        if (klu_sym) {
            klu_free_symbolic(&klu_sym, &common);
        }
        analysed_pattern = 0;
    }
};

LinearSolver::LinearSolver(LinearSolverKind kind, LuPrecision precondition)
    : kind_(kind), precondition_(precondition), impl_(std::make_unique<Impl>()) {}
LinearSolver::~LinearSolver() = default;

bool LinearSolver::factorise(const Eigen::SparseMatrix<double>& A, std::uint64_t pattern_id,
                             std::string& error) {
    Impl& s = *impl_;
    if (!A.isCompressed() || A.rows() != A.cols()) {
        error = "the linear solver needs a square compressed matrix";
        return false;
    }
    const int n = static_cast<int>(A.rows());
    int* Ap = const_cast<int*>(A.outerIndexPtr()); // SuiteSparse's C API is not const-correct
    int* Ai = const_cast<int*>(A.innerIndexPtr());
    double* Ax = const_cast<double*>(A.valuePtr());
    if (!std::all_of(Ax, Ax + A.nonZeros(), [](double v) { return std::isfinite(v); })) {
        error = "the tangent matrix has non-finite entries";
        return false;
    }
    s.release_numeric();
    if (n == 0) { // nothing free: every DOF prescribed
        s.n = 0;
        s.factorised = true;
        return true;
    }
    if (pattern_id != s.analysed_pattern || n != s.n) {
        s.release();
        s.n = n;
        if (kind_ == LinearSolverKind::umfpack) {
            const int st =
                umfpack_di_symbolic(n, n, Ap, Ai, Ax, &s.umf_symbolic, s.control, s.info);
            if (st != UMFPACK_OK) {
                error = fmt::format("UMFPACK symbolic analysis failed (status {})", st);
                return false;
            }
        } else {
            s.klu_sym = klu_analyze(n, Ap, Ai, &s.common);
            if (!s.klu_sym) {
                error = fmt::format("KLU analysis failed (status {})", s.common.status);
                return false;
            }
        }
        s.analysed_pattern = pattern_id;
        ++counters_.symbolic_analyses;
    }
    ++counters_.numeric_factorisations;
    s.A = &A;
    if (kind_ == LinearSolverKind::umfpack) {
        const auto start = std::chrono::steady_clock::now();
        const int st =
            umfpack_di_numeric(Ap, Ai, Ax, s.umf_symbolic, &s.umf_numeric, s.control, s.info);
        counters_.factor_seconds +=
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (st == UMFPACK_WARNING_singular_matrix) {
            error = "the tangent matrix is singular (UMFPACK: a zero pivot): is every "
                    "rigid-body motion prevented?";
            return false;
        }
        if (st != UMFPACK_OK) {
            error = fmt::format("UMFPACK numeric factorisation failed (status {})", st);
            return false;
        }
        counters_.factor_flops += s.info[UMFPACK_FLOPS];
        counters_.factor_nonzeros =
            static_cast<long>(s.info[UMFPACK_LNZ] + s.info[UMFPACK_UNZ] - n);
        counters_.factor_strategy = s.info[UMFPACK_STRATEGY_USED] == UMFPACK_STRATEGY_SYMMETRIC
                                        ? "symmetric"
                                        : "unsymmetric";
        if (!(s.info[UMFPACK_RCOND] >= singular_rcond)) {
            error = fmt::format("the tangent matrix is numerically singular (UMFPACK pivot "
                                "ratio {:.2e}): is every rigid-body motion prevented?",
                                s.info[UMFPACK_RCOND]);
            return false;
        }
    } else {
        s.klu_num = klu_factor(Ap, Ai, Ax, s.klu_sym, &s.common);
        if (!s.klu_num || s.common.status == KLU_SINGULAR) {
            error = s.common.status == KLU_SINGULAR
                        ? std::string("the tangent matrix is singular (KLU: a zero pivot): is "
                                      "every rigid-body motion prevented?")
                        : fmt::format("KLU factorisation failed (status {})", s.common.status);
            return false;
        }
        if (!klu_rcond(s.klu_sym, s.klu_num, &s.common) || !(s.common.rcond >= singular_rcond)) {
            error = fmt::format("the tangent matrix is numerically singular (KLU pivot ratio "
                                "{:.2e}): is every rigid-body motion prevented?",
                                s.common.rcond);
            return false;
        }
    }
    s.factorised = true;
    return true;
}

bool LinearSolver::solve(const double* b, double* x, std::string& error) {
    Impl& s = *impl_;
    if (!s.factorised) {
        error = "solve() without a successful factorisation";
        return false;
    }
    ++counters_.solves;
    if (s.n == 0) {
        return true;
    }
    if (kind_ == LinearSolverKind::umfpack) {
        const Eigen::SparseMatrix<double>& A = *s.A;
        const int st = umfpack_di_solve(UMFPACK_A, A.outerIndexPtr(), A.innerIndexPtr(),
                                        A.valuePtr(), x, b, s.umf_numeric, s.control, s.info);
        if (st != UMFPACK_OK) {
            error = fmt::format("UMFPACK solve failed (status {})", st);
            return false;
        }
    } else {
        std::copy(b, b + s.n, x);
        if (!klu_solve(s.klu_sym, s.klu_num, s.n, 1, x, &s.common)) {
            error = fmt::format("KLU solve failed (status {})", s.common.status);
            return false;
        }
    }
    if (!std::all_of(x, x + s.n, [](double v) { return std::isfinite(v); })) {
        error = "the linear solve gave non-finite values";
        return false;
    }
    return true;
}

bool LinearSolver::holds_factorisation(std::uint64_t pattern_id) const {
    return impl_->factorised && impl_->n > 0 && impl_->analysed_pattern == pattern_id;
}

bool LinearSolver::solve_preconditioned(const Eigen::SparseMatrix<double>& A, const double* b,
                                        double* x, double rtol, int max_iterations) {
    Impl& s = *impl_;
    if (!s.factorised || A.rows() != s.n || !A.isCompressed()) {
        return false;
    }
    ++counters_.krylov_solves;
    const auto start = std::chrono::steady_clock::now();
    const int n = s.n;
    // y = A v in column blocks, the same sums for any thread count (fem/blocked_product.hpp).
    s.product.prepare(A);
    auto apply_a = [&](const auto& v, Eigen::VectorXd& y) {
        s.product.multiply(v.data(), y.data());
    };
    if (kind_ == LinearSolverKind::umfpack && !s.lu_tried) {
        s.lu_tried = true;
        // failed: UMFPACK's own solve below
        s.lu.extract_umfpack(s.umf_numeric, n, true, precondition_);
        counters_.copy_seconds +=
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    std::vector<double> rhs_copy(static_cast<std::size_t>(n));
    auto apply_m_inverse = [&](const auto& v, Eigen::VectorXd& z) {
        const ScopedSeconds clock(counters_.precondition_seconds);
        for (int i = 0; i < n; ++i) {
            rhs_copy[static_cast<std::size_t>(i)] = v[i];
        }
        if (!s.lu.empty()) {
            s.lu.solve(rhs_copy.data(), z.data());
        } else if (kind_ == LinearSolverKind::umfpack) {
            const int st =
                umfpack_di_solve(UMFPACK_A, A.outerIndexPtr(), A.innerIndexPtr(), A.valuePtr(),
                                 z.data(), rhs_copy.data(), s.umf_numeric, s.control_plain, s.info);
            if (st != UMFPACK_OK) {
                return false;
            }
        } else {
            if (!klu_solve(s.klu_sym, s.klu_num, n, 1, rhs_copy.data(), &s.common)) {
                return false;
            }
            std::copy(rhs_copy.begin(), rhs_copy.end(), z.data());
        }
        return z.allFinite();
    };
    const Eigen::Map<const Eigen::VectorXd> bv(b, n);
    Eigen::VectorXd xv = Eigen::VectorXd::Zero(n);
    const GmresOutcome o = gmres(apply_a, apply_m_inverse, Eigen::VectorXd(bv), xv, rtol,
                                 max_iterations, max_iterations);
    counters_.krylov_iterations += o.iterations;
    counters_.krylov_seconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!o.converged || !xv.allFinite()) {
        ++counters_.krylov_fallbacks;
        return false;
    }
    std::copy(xv.data(), xv.data() + n, x);
    ++counters_.solves;
    return true;
}

} // namespace ifsim::fem
