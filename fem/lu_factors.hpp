#pragma once
// The factors of a sparse LU factorisation, P R A Q = L U, held as plain compressed rows (L)
// and columns (U) for repeated triangular solves. GMRES with a held factorisation applies it
// 10-30 times per Newton system; UMFPACK's own solve rebuilds each front's pattern on every
// call, and on the fine §6 mesh (13.4 k equations, 7.5 M factor entries) those solves were
// 58 % of the run's samples (docs/performance.md, "Preconditioner solves"). Two streaming
// passes over the copied arrays do the same arithmetic.
//
// Two threads: a nested-dissection ordering leaves the first pivots in independent blocks
// (the two halves below the top separator). The pivots before `split` are grouped into two
// sets with no entry of L or U between them; the forward pass runs the two sets side by side
// and then the rest, the backward pass the rest and then the two sets. Each row and column is
// computed by the same operations in the same order whichever thread runs it, so the result
// is bitwise the serial one for any thread count.

#include <algorithm>
#include <array>
#include <vector>

namespace ifsim::fem {

class LuFactors {
public:
    // Copies the factors out of an UMFPACK numeric object of an n x n matrix and, with
    // `two_sets`, finds the independent pivot sets. false: UMFPACK refused (memory) or a pivot
    // of U is zero; the object is then empty.
    bool extract_umfpack(void* numeric, int n, bool two_sets = true);
    void clear();
    bool empty() const { return n_ == 0; }

    // x = A^-1 b with A the factorised matrix (x and b of length n; they may alias). Runs the
    // two pivot sets as two TBB tasks (serially under a one-thread limit). Uses the object's
    // workspace: one solve at a time per object.
    void solve(const double* b, double* x) const;

    int size() const { return n_; }
    long nonzeros() const { return static_cast<long>(lx_.size() + ux_.size()); }
    // The factor entries in the larger of the two pivot sets and in the serial rest: a solve
    // on two threads costs about (largest_set + serial) / nonzeros of one on one thread.
    long largest_set_nonzeros() const { return std::max(set_nonzeros_[0], set_nonzeros_[1]); }
    long serial_nonzeros() const { return serial_nonzeros_; }

private:
    void find_two_sets();
    void forward_row(int k, double* z) const;
    void backward_column(int k, double* z) const;

    int n_ = 0;
    std::vector<int> lp_, lj_; // L by rows, unit diagonal last in each row
    std::vector<double> lx_;
    std::vector<int> up_, ui_; // U by columns, diagonal last in each column
    std::vector<double> ux_;
    std::vector<int> p_, q_;        // row and column permutations: row P[k] of A is pivot row k
    std::vector<double> row_scale_; // multiplies row i of A (reciprocals taken at extraction)
    int split_ = 0;                 // pivots [0, split_) are in sets_, the rest serial
    std::array<std::vector<int>, 2> sets_; // pivot indices, increasing
    std::array<long, 2> set_nonzeros_{0, 0};
    long serial_nonzeros_ = 0;
    mutable std::vector<double> work_;
};

} // namespace ifsim::fem
