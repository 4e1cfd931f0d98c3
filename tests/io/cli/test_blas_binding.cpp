// The BLAS UMFPACK calls is the one Debian's libblas.so.3 alternative selects, also in a binary
// that links Ceres (whose static library names ATLAS's libf77blas.so.3: linked first, that
// library's dgemm_ took over UMFPACK's fronts and doubled the factorisation time of the fine
// §6 mesh). This suite links ifsim_io, as the ifsim executable does.
#include "fem/blas_binding.hpp"
#include "fem/linear_solver.hpp"

#include <gtest/gtest.h>

#include <Eigen/SparseCore>

namespace {

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
    ifsim::fem::LinearSolver solver;
    Eigen::SparseMatrix<double> a(2, 2);
    a.insert(0, 0) = 2.0;
    a.insert(1, 1) = 4.0;
    a.makeCompressed();
    std::string error;
    ASSERT_TRUE(solver.factorise(a, 1, error)) << error;
    if (!ifsim::fem::blas_binding().openblas) {
        GTEST_SKIP() << "the BLAS is not OpenBLAS";
    }
    EXPECT_EQ(ifsim::fem::blas_threads(), 1);
}

} // namespace
