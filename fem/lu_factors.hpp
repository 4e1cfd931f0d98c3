#pragma once
// The factors of a sparse LU factorisation, P R A Q = L U, held for repeated triangular solves:
// GMRES with a held factorisation applies it 10-30 times per Newton system. UMFPACK's own
// solve rebuilds each front's pattern on every call; on the fine §6 mesh those solves were
// 58 % of the run's samples (docs/performance.md, "Preconditioner solves").
//
// Layout: L by rows and U by columns, each row (column) cut into runs of consecutive column
// (row) indices. A multifrontal factorisation's pivots of one front are consecutive, so a row
// of L is a few long runs, one per front that updates it; a run is a dense dot product (L) or
// axpy (U) on a contiguous piece of the solution, with one index per run instead of one per
// entry.
//
// Precision: the values are held in double or in single precision. As GMRES's preconditioner
// the factors are an approximate inverse anyway (of an older tangent); single precision halves
// the bytes a solve streams, and a solve is bound by them. The arithmetic stays in double;
// U's diagonal is kept in double.
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

enum class LuPrecision { double_precision, single_precision };

class LuFactors {
public:
    // Copies the factors out of an UMFPACK numeric object of an n x n matrix, in `precision`,
    // and, with `two_sets`, finds the independent pivot sets. false: UMFPACK refused (memory)
    // or a pivot of U is zero; the object is then empty.
    bool extract_umfpack(void* numeric, int n, bool two_sets = true,
                         LuPrecision precision = LuPrecision::double_precision);
    void clear();
    bool empty() const { return n_ == 0; }

    // x = A^-1 b with A the factorised matrix (x and b of length n; they may alias). Runs the
    // two pivot sets as two TBB tasks (serially under a one-thread limit). Uses the object's
    // workspace: one solve at a time per object.
    void solve(const double* b, double* x) const;

    int size() const { return n_; }
    LuPrecision precision() const { return precision_; }
    // Entries of L and U held, U's diagonal included and L's unit diagonal not.
    long nonzeros() const { return static_cast<long>(lval_count_ + uval_count_) + n_; }
    // Runs of consecutive indices over both factors (one index each).
    long runs() const { return static_cast<long>(lrun_first_.size() + urun_first_.size()); }
    // The factor entries in the larger of the two pivot sets and in the serial rest: a solve
    // on two threads costs about (largest_set + serial) / nonzeros of one on one thread.
    long largest_set_nonzeros() const { return std::max(set_nonzeros_[0], set_nonzeros_[1]); }
    long serial_nonzeros() const { return serial_nonzeros_; }

private:
    template <class Real>
    void solve_with(const Real* lx, const Real* ux, double* z) const;
    template <class Real>
    void forward_row(int k, const Real* lx, double* z) const;
    template <class Real>
    void backward_column(int k, const Real* ux, double* z) const;
    void find_two_sets();
    long entries_of_pivot(int k) const;
    template <class Visit>
    void for_each_run(int k, const Visit& visit) const;

    int n_ = 0;
    LuPrecision precision_ = LuPrecision::double_precision;
    // L by rows, without the unit diagonal: row k holds runs [lrow_[k], lrow_[k + 1]); run r
    // covers columns lrun_first_[r] ... and values [lrun_value_[r], lrun_value_[r + 1]).
    std::vector<int> lrow_, lrun_first_, lrun_value_;
    // U by columns, without the diagonal (udiag_), laid out as L with rows for columns.
    std::vector<int> ucol_, urun_first_, urun_value_;
    std::vector<double> udiag_;
    std::size_t lval_count_ = 0, uval_count_ = 0;
    std::vector<double> lx_, ux_;    // double precision values
    std::vector<float> lx_s_, ux_s_; // single precision values
    std::vector<int> p_, q_;         // row and column permutations: row P[k] of A is pivot k
    std::vector<double> row_scale_;  // multiplies row i of A (reciprocals taken at extraction)
    int split_ = 0;                  // pivots [0, split_) are in sets_, the rest serial
    std::array<std::vector<int>, 2> sets_; // pivot indices, increasing
    std::array<long, 2> set_nonzeros_{0, 0};
    long serial_nonzeros_ = 0;
    mutable std::vector<double> work_;
    // UMFPACK's arrays, kept between copies so that a copy does not map fresh pages.
    struct Scratch {
        std::vector<int> lp, lj, up, ui;
        std::vector<double> lx, ux;
    };
    Scratch scratch_;
};

} // namespace ifsim::fem
