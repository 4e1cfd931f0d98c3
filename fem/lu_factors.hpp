#pragma once
// The factors of a sparse LU factorisation, P R A Q = L U, held as plain compressed rows (L)
// and columns (U) for repeated triangular solves. GMRES with a held factorisation applies it
// 10-20 times per Newton system; UMFPACK's own solve rebuilds each front's pattern on every
// call, and on the fine §6 mesh (13.4 k equations, 7.5 M factor entries) those solves were
// 58 % of the run's samples (docs/performance.md, "Preconditioner solves"). Two streaming
// passes over the extracted arrays do the same arithmetic. Serial and in a fixed order: the
// result does not depend on the thread count.

#include <vector>

namespace ifsim::fem {

class LuFactors {
public:
    // Copies the factors out of an UMFPACK numeric object of an n x n matrix. false: UMFPACK
    // refused (memory) or a pivot of U is zero; the object is then empty.
    bool extract_umfpack(void* numeric, int n);
    void clear();
    bool empty() const { return n_ == 0; }

    // x = A^-1 b with A the factorised matrix (x and b of length n; they may alias).
    void solve(const double* b, double* x) const;

    int size() const { return n_; }
    long nonzeros() const { return static_cast<long>(lx_.size() + ux_.size()); }

private:
    int n_ = 0;
    std::vector<int> lp_, lj_; // L by rows, unit diagonal last in each row
    std::vector<double> lx_;
    std::vector<int> up_, ui_; // U by columns, diagonal last in each column
    std::vector<double> ux_;
    std::vector<int> p_, q_;        // row and column permutations: row P[k] of A is pivot row k
    std::vector<double> row_scale_; // multiplies row i of A (reciprocals taken at extraction)
    mutable std::vector<double> work_;
};

} // namespace ifsim::fem
