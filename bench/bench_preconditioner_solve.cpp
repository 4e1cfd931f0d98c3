// One preconditioner application of the reused-factorisation GMRES (fem/linear_solver.cpp):
// UMFPACK's own solve against the factors copied out into plain rows and columns
// (fem/lu_factors.hpp), and the price of the copy, on a matrix with the pattern of a 3D hex-8
// mesh (each node coupled to its 26 neighbours, 3 DOFs per node). The grid of the fine §6
// mesh's soil (25 x 6 x 33 nodes, 14 850 equations) is the default size. The ratio printed at
// the end is UMFPACK over the copied factors, per solve, from this one run.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Sparse>
#include <benchmark/benchmark.h>
#include <suitesparse/umfpack.h>
#include <tbb/global_control.h>

#include "fem/blas_binding.hpp"
#include "fem/blocked_product.hpp"
#include "fem/lu_factors.hpp"

namespace {

// A hex-8-like stiffness pattern: 3x3 blocks between every pair of neighbouring nodes,
// diagonally dominant, unsymmetric (as the contact and hypoplastic tangents are).
Eigen::SparseMatrix<double> hex_pattern_matrix(int nx, int ny, int nz) {
    auto node = [&](int i, int j, int k) { return (k * ny + j) * nx + i; };
    std::vector<Eigen::Triplet<double>> t;
    for (int k = 0; k < nz; ++k) {
        for (int j = 0; j < ny; ++j) {
            for (int i = 0; i < nx; ++i) {
                const int a = node(i, j, k);
                for (int dk = -1; dk <= 1; ++dk) {
                    for (int dj = -1; dj <= 1; ++dj) {
                        for (int di = -1; di <= 1; ++di) {
                            const int ii = i + di, jj = j + dj, kk = k + dk;
                            if (ii < 0 || jj < 0 || kk < 0 || ii >= nx || jj >= ny || kk >= nz) {
                                continue;
                            }
                            const int b = node(ii, jj, kk);
                            for (int r = 0; r < 3; ++r) {
                                for (int c = 0; c < 3; ++c) {
                                    const double v =
                                        a == b ? (r == c ? 60.0 : 0.3 * (r - c))
                                               : -0.8 - 0.1 * std::sin(3.0 * a + 7.0 * b + r + c);
                                    t.emplace_back(3 * a + r, 3 * b + c, v);
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    const int n = 3 * nx * ny * nz;
    Eigen::SparseMatrix<double> A(n, n);
    A.setFromTriplets(t.begin(), t.end());
    A.makeCompressed();
    return A;
}

struct Factorised {
    Eigen::SparseMatrix<double> A;
    void* symbolic = nullptr;
    void* numeric = nullptr;
    double control[UMFPACK_CONTROL];
    double info[UMFPACK_INFO];
    explicit Factorised(int nx, int ny, int nz) : A(hex_pattern_matrix(nx, ny, nz)) {
        // OpenBLAS as ifsim runs it: one thread, kernels for this CPU (OPENBLAS_CORETYPE=Prescott
        // measures the fallback Debian 12's OpenBLAS takes on CPUs newer than itself)
        ifsim::fem::configure_blas();
        umfpack_di_defaults(control);
        control[UMFPACK_ORDERING] = UMFPACK_ORDERING_CHOLMOD; // as fem/linear_solver.cpp
        control[UMFPACK_IRSTEP] = 0;
        const int n = static_cast<int>(A.rows());
        umfpack_di_symbolic(n, n, A.outerIndexPtr(), A.innerIndexPtr(), A.valuePtr(), &symbolic,
                            control, info);
        umfpack_di_numeric(A.outerIndexPtr(), A.innerIndexPtr(), A.valuePtr(), symbolic, &numeric,
                           control, info);
    }
    ~Factorised() {
        umfpack_di_free_numeric(&numeric);
        umfpack_di_free_symbolic(&symbolic);
    }
};

void set_counters(benchmark::State& state, const Factorised& f) {
    state.counters["equations"] = static_cast<double>(f.A.rows());
    const std::string core = ifsim::fem::blas_binding().openblas_core;
    state.SetLabel(core.empty() ? "blas: not OpenBLAS" : "OpenBLAS " + core);
    state.counters["factor_nonzeros"] = f.info[UMFPACK_LNZ] + f.info[UMFPACK_UNZ];
}

void BM_UmfpackSolve(benchmark::State& state) {
    Factorised f(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)),
                 static_cast<int>(state.range(2)));
    const int n = static_cast<int>(f.A.rows());
    std::vector<double> b(static_cast<std::size_t>(n), 1.0), x(static_cast<std::size_t>(n));
    for (auto _ : state) {
        umfpack_di_solve(UMFPACK_A, f.A.outerIndexPtr(), f.A.innerIndexPtr(), f.A.valuePtr(),
                         x.data(), b.data(), f.numeric, f.control, f.info);
        benchmark::DoNotOptimize(x.data());
    }
    set_counters(state, f);
}

// range(3): threads (the two pivot sets run as two tasks; one thread runs them in turn);
// range(4): 1 for the factors held in single precision, 0 for double.
void BM_CopiedFactorsSolve(benchmark::State& state) {
    Factorised f(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)),
                 static_cast<int>(state.range(2)));
    const int n = static_cast<int>(f.A.rows());
    tbb::global_control threads(tbb::global_control::max_allowed_parallelism,
                                static_cast<std::size_t>(state.range(3)));
    ifsim::fem::LuFactors lu;
    const auto precision = state.range(4) ? ifsim::fem::LuPrecision::single_precision
                                          : ifsim::fem::LuPrecision::double_precision;
    if (!lu.extract_umfpack(f.numeric, n, true, precision)) {
        state.SkipWithError("copying the factors failed");
        return;
    }
    std::vector<double> b(static_cast<std::size_t>(n), 1.0), x(static_cast<std::size_t>(n));
    for (auto _ : state) {
        lu.solve(b.data(), x.data());
        benchmark::DoNotOptimize(x.data());
    }
    set_counters(state, f);
    // The two-thread bound from the sets: (larger set + serial rest) / all factor entries.
    state.counters["two_thread_share"] =
        static_cast<double>(lu.largest_set_nonzeros() + lu.serial_nonzeros()) /
        static_cast<double>(lu.nonzeros());
    state.counters["entries_per_run"] =
        static_cast<double>(lu.nonzeros() - n) / static_cast<double>(lu.runs());
    // The relative residual of the solve: what single precision costs a preconditioner.
    Eigen::VectorXd r = Eigen::Map<const Eigen::VectorXd>(b.data(), n);
    r -= f.A * Eigen::Map<const Eigen::VectorXd>(x.data(), n);
    state.counters["relative_residual"] = r.norm() / std::sqrt(static_cast<double>(n));
}

void BM_CopyFactors(benchmark::State& state) {
    Factorised f(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)),
                 static_cast<int>(state.range(2)));
    const int n = static_cast<int>(f.A.rows());
    ifsim::fem::LuFactors lu;
    for (auto _ : state) {
        lu.extract_umfpack(f.numeric, n);
        benchmark::DoNotOptimize(lu.nonzeros());
    }
    set_counters(state, f);
}

void BM_Factorise(benchmark::State& state) {
    Factorised f(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)),
                 static_cast<int>(state.range(2)));
    for (auto _ : state) {
        void* numeric = nullptr;
        umfpack_di_numeric(f.A.outerIndexPtr(), f.A.innerIndexPtr(), f.A.valuePtr(), f.symbolic,
                           &numeric, f.control, f.info);
        umfpack_di_free_numeric(&numeric);
    }
    set_counters(state, f);
}

// GMRES's product with the tangent (fem/blocked_product.hpp), range(3) threads; the serial
// column scatter it replaced at range(3) = 0.
void BM_TangentProduct(benchmark::State& state) {
    const Eigen::SparseMatrix<double> A =
        hex_pattern_matrix(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)),
                           static_cast<int>(state.range(2)));
    const int n = static_cast<int>(A.rows());
    const int threads = static_cast<int>(state.range(3));
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                              static_cast<std::size_t>(std::max(threads, 1)));
    std::vector<double> v(static_cast<std::size_t>(n), 1.0), y(static_cast<std::size_t>(n));
    ifsim::fem::BlockedProduct product;
    product.prepare(A);
    for (auto _ : state) {
        if (threads == 0) {
            std::fill(y.begin(), y.end(), 0.0);
            for (int j = 0; j < n; ++j) {
                for (int p = A.outerIndexPtr()[j]; p < A.outerIndexPtr()[j + 1]; ++p) {
                    y[static_cast<std::size_t>(A.innerIndexPtr()[p])] +=
                        A.valuePtr()[p] * v[static_cast<std::size_t>(j)];
                }
            }
        } else {
            product.multiply(v.data(), y.data());
        }
        benchmark::DoNotOptimize(y.data());
    }
    state.counters["entries"] = static_cast<double>(A.nonZeros());
}

// The fine §6 soil grid and a smaller one.
#define IFSIM_SIZES Args({25, 6, 33})->Args({13, 6, 17})->Unit(benchmark::kMillisecond)
BENCHMARK(BM_UmfpackSolve)->IFSIM_SIZES;
BENCHMARK(BM_CopiedFactorsSolve)
    ->Args({25, 6, 33, 1, 0})
    ->Args({25, 6, 33, 2, 0})
    ->Args({25, 6, 33, 1, 1})
    ->Args({25, 6, 33, 2, 1})
    ->Args({13, 6, 17, 1, 0})
    ->Args({13, 6, 17, 2, 0})
    ->Args({13, 6, 17, 1, 1})
    ->Args({13, 6, 17, 2, 1})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CopyFactors)->IFSIM_SIZES;
BENCHMARK(BM_Factorise)->IFSIM_SIZES;
BENCHMARK(BM_TangentProduct)
    ->Args({25, 6, 33, 0})
    ->Args({25, 6, 33, 1})
    ->Args({25, 6, 33, 2})
    ->Unit(benchmark::kMicrosecond);

// Prints UMFPACK's solve over the copied factors' (one thread), the copied factors' one thread
// over two, and a factorisation and the copy in one-thread copied-factor solves.
class PreconditionerReporter : public benchmark::ConsoleReporter {
public:
    void ReportRuns(const std::vector<Run>& runs) override {
        ConsoleReporter::ReportRuns(runs);
        for (const Run& r : runs) {
            seconds_[r.benchmark_name()] = r.GetAdjustedRealTime();
        }
    }
    void Finalize() override {
        ConsoleReporter::Finalize();
        for (const char* size : {"25/6/33", "13/6/17"}) {
            const std::string tail = std::string("/") + size;
            const auto get = [&](const char* name, const char* threads) {
                const auto it = seconds_.find(std::string(name) + tail + threads);
                return it == seconds_.end() ? std::nan("") : it->second;
            };
            const double one = get("BM_CopiedFactorsSolve", "/1/0");
            std::printf("grid %s: UMFPACK solve / copied-factor solve = %.2f; copied-factor "
                        "solve, 1 thread / 2 threads = %.2f; double / single precision = %.2f "
                        "(1 thread), %.2f (2 threads); a factorisation = %.1f copied-factor "
                        "solves; the copy = %.1f\n",
                        size, get("BM_UmfpackSolve", "") / one,
                        one / get("BM_CopiedFactorsSolve", "/2/0"),
                        one / get("BM_CopiedFactorsSolve", "/1/1"),
                        get("BM_CopiedFactorsSolve", "/2/0") / get("BM_CopiedFactorsSolve", "/2/1"),
                        get("BM_Factorise", "") / one, get("BM_CopyFactors", "") / one);
        }
        const auto product = [&](const char* threads) {
            const auto it = seconds_.find(std::string("BM_TangentProduct/25/6/33/") + threads);
            return it == seconds_.end() ? std::nan("") : it->second;
        };
        std::printf("tangent product, grid 25/6/33: serial scatter / blocks on 1 thread = %.2f; "
                    "blocks, 1 thread / 2 threads = %.2f\n",
                    product("0") / product("1"), product("1") / product("2"));
    }

private:
    std::map<std::string, double> seconds_;
};

} // namespace

int main(int argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    PreconditionerReporter reporter;
    benchmark::RunSpecifiedBenchmarks(&reporter);
    benchmark::Shutdown();
    return 0;
}
