#include "fem/blocked_product.hpp"

#include <algorithm>

#include <tbb/parallel_for.h>

namespace ifsim::fem {

void BlockedProduct::prepare(const Eigen::SparseMatrix<double>& A) {
    A_ = &A;
    const int rows = static_cast<int>(A.rows());
    const int cols = static_cast<int>(A.cols());
    const int* outer = A.outerIndexPtr();
    const int* inner = A.innerIndexPtr();
    // Entries per row block about equal: count the rows' entries once.
    std::vector<long long> row_end(static_cast<std::size_t>(rows) + 1, 0);
    for (int k = 0; k < outer[cols]; ++k) {
        ++row_end[static_cast<std::size_t>(inner[k]) + 1];
    }
    for (int i = 0; i < rows; ++i) {
        row_end[static_cast<std::size_t>(i) + 1] += row_end[static_cast<std::size_t>(i)];
    }
    first_row_[0] = 0;
    for (int b = 1; b < blocks; ++b) {
        const long long target = row_end[static_cast<std::size_t>(rows)] * b / blocks;
        first_row_[static_cast<std::size_t>(b)] =
            std::max(first_row_[static_cast<std::size_t>(b) - 1],
                     static_cast<int>(std::lower_bound(row_end.begin(), row_end.end(), target) -
                                      row_end.begin()));
    }
    first_row_[blocks] = rows;
    stretch_start_.resize(static_cast<std::size_t>(blocks) * static_cast<std::size_t>(cols + 1));
    for (int b = 0; b < blocks; ++b) {
        int* start = stretch_start_.data() + static_cast<std::size_t>(b) * (cols + 1);
        for (int j = 0; j < cols; ++j) {
            start[j] = static_cast<int>(std::lower_bound(inner + outer[j], inner + outer[j + 1],
                                                         first_row_[static_cast<std::size_t>(b)]) -
                                        inner);
        }
        start[cols] = outer[cols];
    }
}

void BlockedProduct::multiply(const double* v, double* y) const {
    const Eigen::SparseMatrix<double>& A = *A_;
    const int cols = static_cast<int>(A.cols());
    const int* outer = A.outerIndexPtr();
    const int* inner = A.innerIndexPtr();
    const double* val = A.valuePtr();
    tbb::parallel_for(0, blocks, [&](int b) {
        std::fill(y + first_row_[static_cast<std::size_t>(b)],
                  y + first_row_[static_cast<std::size_t>(b) + 1], 0.0);
        const int* start = stretch_start_.data() + static_cast<std::size_t>(b) * (cols + 1);
        const int* end = b + 1 < blocks ? start + (cols + 1) : outer;
        const int end_shift = b + 1 < blocks ? 0 : 1; // the last block ends at outer[j + 1]
        for (int j = 0; j < cols; ++j) {
            const double vj = v[j];
            for (int k = start[j]; k < end[j + end_shift]; ++k) {
                y[inner[k]] += val[k] * vj;
            }
        }
    });
}

} // namespace ifsim::fem
