// The factors copied out of UMFPACK (fem/lu_factors.hpp) solve like the factorisation they came
// from: against a dense LU on a matrix that forces off-diagonal pivots (zero diagonal, so the
// row and column permutations differ), under each of UMFPACK's row scalings, in double and to
// single precision's rounding in single, and an empty object after a failed copy; every factor
// entry is held once, in runs of consecutive indices; the two independent pivot sets of a
// nested-dissection ordering run on two threads and give bitwise the serial solve.
#include <gtest/gtest.h>

#include <vector>

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <suitesparse/umfpack.h>
#include <tbb/global_control.h>

#include "fem/lu_factors.hpp"

using ifsim::fem::LuFactors;
using ifsim::fem::LuPrecision;

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

// UMFPACK's factorisation of A with one control entry set, freed at the end of the scope.
struct Umfpack {
    void* symbolic = nullptr;
    void* numeric = nullptr;
    bool ok = false;
    Umfpack(const Eigen::SparseMatrix<double>& A, int key, double value) {
        double control[UMFPACK_CONTROL], info[UMFPACK_INFO];
        umfpack_di_defaults(control);
        control[key] = value;
        const int n = static_cast<int>(A.rows());
        ok = umfpack_di_symbolic(n, n, A.outerIndexPtr(), A.innerIndexPtr(), A.valuePtr(),
                                 &symbolic, control, info) == UMFPACK_OK &&
             umfpack_di_numeric(A.outerIndexPtr(), A.innerIndexPtr(), A.valuePtr(), symbolic,
                                &numeric, control, info) == UMFPACK_OK;
    }
    ~Umfpack() {
        if (numeric) {
            umfpack_di_free_numeric(&numeric);
        }
        if (symbolic) {
            umfpack_di_free_symbolic(&symbolic);
        }
    }
    Umfpack(const Umfpack&) = delete;
    Umfpack& operator=(const Umfpack&) = delete;
};

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
        const Umfpack f(A, UMFPACK_SCALE, scale);
        ASSERT_TRUE(f.ok);
        int lnz = 0, unz = 0, n_row = 0, n_col = 0, nz_udiag = 0;
        ASSERT_EQ(umfpack_di_get_lunz(&lnz, &unz, &n_row, &n_col, &nz_udiag, f.numeric),
                  UMFPACK_OK);
        // Single precision: the values rounded to 6e-8, so the solve is off by that times the
        // (scaled) matrix's condition number, small here.
        for (const auto& [precision, tolerance] :
             {std::pair{LuPrecision::double_precision, 1e-12},
              std::pair{LuPrecision::single_precision, 1e-5}}) {
            LuFactors lu;
            ASSERT_TRUE(lu.extract_umfpack(f.numeric, n, true, precision));
            EXPECT_EQ(lu.size(), n);
            EXPECT_EQ(lu.precision(), precision);
            // Every entry of L (its unit diagonal not held) and U once.
            EXPECT_EQ(lu.nonzeros(), static_cast<long>(lnz - n + unz));
            EXPECT_GT(lu.runs(), 0);
            EXPECT_LE(lu.runs(), lu.nonzeros() - n);
            Eigen::VectorXd x(n);
            lu.solve(b.data(), x.data());
            const double error = (x - ref).norm() / ref.norm();
            EXPECT_LT(error, tolerance) << "scaling " << scale;
            if (precision == LuPrecision::single_precision) {
                EXPECT_GT(error, 1e-12) << "the values were not rounded to single precision";
            }
            // In place, as the documentation allows.
            Eigen::VectorXd y = b;
            lu.solve(y.data(), y.data());
            EXPECT_EQ(y, x);
            // The wrong size is refused and leaves the object empty.
            EXPECT_FALSE(lu.extract_umfpack(f.numeric, n + 1));
            EXPECT_TRUE(lu.empty());
        }
    }
}

namespace {

// A 2D grid Laplacian with a small unsymmetric part: METIS orders it by nested dissection.
Eigen::SparseMatrix<double> grid_matrix(int m) {
    std::vector<Eigen::Triplet<double>> t;
    auto id = [m](int i, int j) { return j * m + i; };
    for (int j = 0; j < m; ++j) {
        for (int i = 0; i < m; ++i) {
            t.emplace_back(id(i, j), id(i, j), 4.2);
            if (i > 0)
                t.emplace_back(id(i, j), id(i - 1, j), -1.1);
            if (i + 1 < m)
                t.emplace_back(id(i, j), id(i + 1, j), -0.9);
            if (j > 0)
                t.emplace_back(id(i, j), id(i, j - 1), -1.0);
            if (j + 1 < m)
                t.emplace_back(id(i, j), id(i, j + 1), -1.0);
        }
    }
    Eigen::SparseMatrix<double> A(m * m, m * m);
    A.setFromTriplets(t.begin(), t.end());
    A.makeCompressed();
    return A;
}

} // namespace

TEST(LuFactors, TwoPivotSetsOnTwoThreadsGiveTheSerialSolveBitwise) {
    const Eigen::SparseMatrix<double> A = grid_matrix(40);
    const int n = static_cast<int>(A.rows());
    const Umfpack f(A, UMFPACK_ORDERING, UMFPACK_ORDERING_CHOLMOD); // as fem/linear_solver.cpp
    ASSERT_TRUE(f.ok);
    LuFactors serial, split;
    ASSERT_TRUE(serial.extract_umfpack(f.numeric, n, false));
    ASSERT_TRUE(split.extract_umfpack(f.numeric, n, true));
    EXPECT_EQ(serial.serial_nonzeros(), serial.nonzeros());
    // The sets are found and are worth a task each: a two-thread solve does well under 90 %
    // of the serial work.
    EXPECT_GT(split.largest_set_nonzeros(), 0);
    EXPECT_LT(split.largest_set_nonzeros() + split.serial_nonzeros(), 0.9 * split.nonzeros());

    Eigen::VectorXd b(n);
    for (int i = 0; i < n; ++i) {
        b(i) = std::cos(0.37 * i) + 1e-3 * i;
    }
    Eigen::VectorXd x_serial(n), x_one(n), x_two(n);
    serial.solve(b.data(), x_serial.data());
    {
        tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
        split.solve(b.data(), x_one.data());
    }
    {
        tbb::global_control two(tbb::global_control::max_allowed_parallelism, 2);
        for (int repeat = 0; repeat < 20; ++repeat) { // the two tasks interleave differently
            split.solve(b.data(), x_two.data());
            ASSERT_EQ(x_two, x_serial) << "repeat " << repeat;
        }
    }
    EXPECT_EQ(x_one, x_serial);
    EXPECT_LT((A * x_serial - b).norm(), 1e-12 * b.norm());
    // A nested-dissection factor is long runs of consecutive indices, not single entries.
    EXPECT_GT(static_cast<double>(split.nonzeros() - n) / static_cast<double>(split.runs()), 4.0);

    // In single precision, the same: the two sets on two threads give the serial solve's bits.
    LuFactors serial_single, split_single;
    ASSERT_TRUE(serial_single.extract_umfpack(f.numeric, n, false, LuPrecision::single_precision));
    ASSERT_TRUE(split_single.extract_umfpack(f.numeric, n, true, LuPrecision::single_precision));
    Eigen::VectorXd s_serial(n), s_two(n);
    serial_single.solve(b.data(), s_serial.data());
    {
        tbb::global_control two(tbb::global_control::max_allowed_parallelism, 2);
        for (int repeat = 0; repeat < 20; ++repeat) {
            split_single.solve(b.data(), s_two.data());
            ASSERT_EQ(s_two, s_serial) << "repeat " << repeat;
        }
    }
    EXPECT_LT((A * s_serial - b).norm(), 1e-5 * b.norm());
}
