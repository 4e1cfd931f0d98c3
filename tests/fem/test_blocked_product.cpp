// GMRES's product with the tangent (fem/blocked_product.hpp): the row blocks give bitwise the
// serial column scatter (and Eigen's product to rounding), on one thread and on two, also where
// blocks are empty (fewer rows than blocks) or one column holds many of the entries.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <Eigen/Sparse>
#include <tbb/global_control.h>

#include "fem/blocked_product.hpp"

using ifsim::fem::BlockedProduct;

namespace {

// Unsymmetric, with rows and columns of very different length.
Eigen::SparseMatrix<double> uneven_matrix(int n) {
    std::vector<Eigen::Triplet<double>> t;
    for (int i = 0; i < n; ++i) {
        t.emplace_back(i, i, 10.0 + 0.1 * i);
        t.emplace_back(i, (7 * i + 3) % n, -1.0 - 0.01 * i);
        t.emplace_back((5 * i + 1) % n, i, std::sin(0.3 * i));
        if (i % 17 == 0) {
            for (int k = 0; k < n; k += 3) {
                t.emplace_back(k, i, 1.0 / (1.0 + k)); // a long column
            }
        }
    }
    Eigen::SparseMatrix<double> A(n, n);
    A.setFromTriplets(t.begin(), t.end());
    A.makeCompressed();
    return A;
}

Eigen::VectorXd blocked(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& v,
                        int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                              static_cast<std::size_t>(threads));
    BlockedProduct product;
    product.prepare(A);
    Eigen::VectorXd y(A.rows());
    product.multiply(v.data(), y.data());
    return y;
}

// The serial column scatter GMRES used before, each y_i summed in column order.
Eigen::VectorXd column_scatter(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& v) {
    Eigen::VectorXd y = Eigen::VectorXd::Zero(A.rows());
    for (int j = 0; j < A.cols(); ++j) {
        for (Eigen::SparseMatrix<double>::InnerIterator it(A, j); it; ++it) {
            y(it.row()) += it.value() * v(j);
        }
    }
    return y;
}

TEST(BlockedProduct, EqualsTheSerialColumnScatterBitwise) {
    for (int n : {1, 2, 5, 400}) {
        const Eigen::SparseMatrix<double> A = uneven_matrix(n);
        Eigen::VectorXd v(n);
        for (int i = 0; i < n; ++i) {
            v(i) = std::cos(1.7 * i) - 0.2;
        }
        const Eigen::VectorXd serial = column_scatter(A, v);
        const Eigen::VectorXd expected = A * v;
        for (int threads : {1, 2}) {
            const Eigen::VectorXd y = blocked(A, v, threads);
            ASSERT_EQ(y.size(), n);
            for (int i = 0; i < n; ++i) {
                ASSERT_EQ(y(i), serial(i)) << "n " << n << " row " << i;
                EXPECT_NEAR(y(i), expected(i), 1e-13 * (1.0 + std::abs(expected(i))));
            }
        }
    }
}

TEST(BlockedProduct, OneThreadAndTwoGiveTheSameBits) {
    const Eigen::SparseMatrix<double> A = uneven_matrix(3000);
    Eigen::VectorXd v(A.cols());
    for (Eigen::Index i = 0; i < v.size(); ++i) {
        v(i) = std::exp(-0.001 * static_cast<double>(i)) * std::sin(static_cast<double>(i));
    }
    const Eigen::VectorXd one = blocked(A, v, 1);
    const Eigen::VectorXd two = blocked(A, v, 2);
    for (Eigen::Index i = 0; i < v.size(); ++i) {
        ASSERT_EQ(one(i), two(i)) << "row " << i;
    }
}

TEST(BlockedProduct, ReusedAfterTheValuesChange) {
    // GMRES prepares once per solve; the tangent's values change between Newton iterations.
    Eigen::SparseMatrix<double> A = uneven_matrix(50);
    BlockedProduct product;
    product.prepare(A);
    const Eigen::VectorXd v = Eigen::VectorXd::LinSpaced(50, -1.0, 2.0);
    Eigen::VectorXd y(50);
    A.coeffs() *= -3.0;
    product.multiply(v.data(), y.data());
    EXPECT_LT((y - A * v).norm(), 1e-12 * (A * v).norm());
}

} // namespace
