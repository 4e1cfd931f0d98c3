#pragma once
// y = A v for a compressed-column matrix, parallel over blocks of rows, with every y_i summed in
// column order exactly as the serial column scatter does: the result is bitwise the serial
// one for any thread count and any block count. Each block walks all columns and takes from
// each the stretch of its own rows (row indices are sorted within a column; the stretch starts
// are found in prepare, once per GMRES solve, a pass over the entries). GMRES's products with the
// tangent (fem/linear_solver.cpp) were serial: 1.6 ms of each 6.9 ms step on the fine §6 mesh.

#include <array>
#include <vector>

#include <Eigen/SparseCore>

namespace ifsim::fem {

class BlockedProduct {
public:
    static constexpr int blocks = 4;

    // Cuts A's rows into blocks of about equal entries; A must stay alive, compressed and of
    // the same pattern while multiply is used (its values may change).
    void prepare(const Eigen::SparseMatrix<double>& A);
    // y = A v; v and y of A's size, not aliased.
    void multiply(const double* v, double* y) const;

private:
    const Eigen::SparseMatrix<double>* A_ = nullptr;
    std::array<int, blocks + 1> first_row_{};
    // stretch_start_[b * (n + 1) + j]: the first entry of column j in row block b; block b's
    // stretch of column j ends where block b + 1's starts (the last block's at outer[j + 1]).
    std::vector<int> stretch_start_;
};

} // namespace ifsim::fem
