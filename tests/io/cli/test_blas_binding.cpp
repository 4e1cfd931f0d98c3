// The BLAS UMFPACK calls is the one Debian's libblas.so.3 alternative selects, also in a binary
// that links Ceres (whose static library names ATLAS's libf77blas.so.3: linked first, that
// library's dgemm_ took over UMFPACK's fronts and doubled the factorisation time of the fine
// §6 mesh). This suite links ifsim_io, as the ifsim executable does.
#include "fem/blas_binding.hpp"
#include "fem/linear_solver.hpp"

#include <cstdlib>

#include <gtest/gtest.h>

#include <Eigen/SparseCore>

namespace {

// A solver's first factorisation: configure_blas has run after it.
bool factorise_once() {
    ifsim::fem::LinearSolver solver;
    Eigen::SparseMatrix<double> a(2, 2);
    a.insert(0, 0) = 2.0;
    a.insert(1, 1) = 4.0;
    a.makeCompressed();
    std::string error;
    return solver.factorise(a, 1, error);
}

TEST(BlasBinding, DgemmComesFromTheLibblasAlternative) {
    const ifsim::fem::BlasBinding b = ifsim::fem::blas_binding();
    ASSERT_FALSE(b.dgemm_library.empty()) << "no dgemm_ in the process: UMFPACK needs a BLAS";
    ASSERT_FALSE(b.libblas_provider.empty()) << "libblas.so.3 is not loaded";
    EXPECT_EQ(b.dgemm_library, b.libblas_provider)
        << "dgemm_ resolves to " << b.dgemm_library << ", not to libblas.so.3's "
        << b.libblas_provider << ": another BLAS is linked before it";
}

TEST(BlasBinding, SolverPinsOpenBlasToOneThread) {
    // After a solver exists, OpenBLAS (when it is the BLAS) runs on one thread.
    ASSERT_TRUE(factorise_once());
    if (!ifsim::fem::blas_binding().openblas) {
        GTEST_SKIP() << "the BLAS is not OpenBLAS";
    }
    EXPECT_EQ(ifsim::fem::blas_threads(), 1);
}

TEST(BlasBinding, OnlyOpenBlasFallbackIsReplacedByTheWidestSetTheCpuCarries) {
    using ifsim::fem::CpuFeatures;
    using ifsim::fem::replacement_core;
    const CpuFeatures avx512{true, true, true}, avx2{false, true, true}, avx{false, false, true},
        sse{};
    EXPECT_EQ(replacement_core("Prescott", avx512), "SkylakeX");
    EXPECT_EQ(replacement_core("PRESCOTT", avx2), "Haswell");
    EXPECT_EQ(replacement_core("Prescott", avx), "Sandybridge");
    EXPECT_EQ(replacement_core("Prescott", sse), ""); // a CPU that old: Prescott is right
    // A set OpenBLAS recognised stays, even where a wider one would run.
    EXPECT_EQ(replacement_core("Haswell", avx512), "");
    EXPECT_EQ(replacement_core("Zen", avx512), "");
    EXPECT_EQ(replacement_core("", avx512), ""); // another BLAS
}

TEST(BlasBinding, SolverRunsOpenBlasOnKernelsTheCpuCarries) {
    // Debian 12's OpenBLAS falls back to its SSE3 kernels on CPUs newer than itself (an Emerald
    // Rapids Xeon here: dgemm 4x slower). Once a solver exists, the set in use is not that
    // fallback on any CPU with AVX, unless the user named one.
    ASSERT_TRUE(factorise_once());
    const ifsim::fem::BlasBinding b = ifsim::fem::blas_binding();
    if (!b.openblas) {
        GTEST_SKIP() << "the BLAS is not OpenBLAS";
    }
    if (std::getenv("OPENBLAS_CORETYPE") != nullptr) {
        GTEST_SKIP() << "OPENBLAS_CORETYPE names the kernel set";
    }
    ASSERT_FALSE(b.openblas_core.empty());
    EXPECT_EQ(ifsim::fem::replacement_core(b.openblas_core, ifsim::fem::cpu_features()), "")
        << "OpenBLAS runs its fallback set " << b.openblas_core << " on a CPU with wider vectors";
    if (!b.openblas_detected_core.empty()) {
        EXPECT_NE(b.openblas_detected_core, b.openblas_core);
    }
    EXPECT_EQ(ifsim::fem::blas_threads(), 1); // switching the set keeps the pinned thread count
}

} // namespace
