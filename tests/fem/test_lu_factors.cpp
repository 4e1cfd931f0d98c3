// The factors copied out of UMFPACK (fem/lu_factors.hpp) solve like the factorisation they came
// from: against a dense LU on a matrix that forces off-diagonal pivots (zero diagonal, so the
// row and column permutations differ), under each of UMFPACK's row scalings, and an empty
// object after a failed copy.
#include <gtest/gtest.h>

#include <vector>

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <suitesparse/umfpack.h>

#include "fem/lu_factors.hpp"

using ifsim::fem::LuFactors;

namespace {

// Unsymmetric, a zero diagonal, rows of very different size (the scaling matters).
Eigen::SparseMatrix<double> zero_diagonal_matrix(int n) {
    std::vector<Eigen::Triplet<double>> t;
    for (int i = 0; i < n; ++i) {
        const double row_size = 1.0 + 1000.0 * (i % 3);
        t.emplace_back(i, (i + 1) % n, row_size * (4.0 + 0.1 * i));
        t.emplace_back(i, (i + 5) % n, row_size * (-1.0 - 0.02 * i));
        t.emplace_back(i, (i + n - 2) % n, row_size * 0.7);
    }
    Eigen::SparseMatrix<double> A(n, n);
    A.setFromTriplets(t.begin(), t.end());
    A.makeCompressed();
    return A;
}

} // namespace

TEST(LuFactors, CopiedFactorsSolveLikeADenseLuUnderEveryScaling) {
    const int n = 60;
    const Eigen::SparseMatrix<double> A = zero_diagonal_matrix(n);
    Eigen::VectorXd b(n);
    for (int i = 0; i < n; ++i) {
        b(i) = std::sin(0.3 * i) + 0.1 * i;
    }
    const Eigen::VectorXd ref = Eigen::MatrixXd(A).fullPivLu().solve(b);
    ASSERT_LT((Eigen::MatrixXd(A) * ref - b).norm(), 1e-9 * b.norm()); // regular
    for (double scale :
         {double(UMFPACK_SCALE_SUM), double(UMFPACK_SCALE_MAX), double(UMFPACK_SCALE_NONE)}) {
        double control[UMFPACK_CONTROL], info[UMFPACK_INFO];
        umfpack_di_defaults(control);
        control[UMFPACK_SCALE] = scale;
        void* symbolic = nullptr;
        void* numeric = nullptr;
        ASSERT_EQ(umfpack_di_symbolic(n, n, A.outerIndexPtr(), A.innerIndexPtr(), A.valuePtr(),
                                      &symbolic, control, info),
                  UMFPACK_OK);
        ASSERT_EQ(umfpack_di_numeric(A.outerIndexPtr(), A.innerIndexPtr(), A.valuePtr(), symbolic,
                                     &numeric, control, info),
                  UMFPACK_OK);
        LuFactors lu;
        ASSERT_TRUE(lu.extract_umfpack(numeric, n));
        EXPECT_EQ(lu.size(), n);
        EXPECT_GE(lu.nonzeros(), A.nonZeros());
        Eigen::VectorXd x(n);
        lu.solve(b.data(), x.data());
        EXPECT_LT((x - ref).norm(), 1e-12 * ref.norm()) << "scaling " << scale;
        // In place, as the documentation allows.
        Eigen::VectorXd y = b;
        lu.solve(y.data(), y.data());
        EXPECT_EQ(y, x);
        // The wrong size is refused and leaves the object empty.
        EXPECT_FALSE(lu.extract_umfpack(numeric, n + 1));
        EXPECT_TRUE(lu.empty());
        umfpack_di_free_numeric(&numeric);
        umfpack_di_free_symbolic(&symbolic);
    }
}
