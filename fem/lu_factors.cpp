#include "fem/lu_factors.hpp"

#include <suitesparse/umfpack.h>

namespace ifsim::fem {

void LuFactors::clear() {
    n_ = 0;
    for (auto* v : {&lp_, &lj_, &up_, &ui_, &p_, &q_}) {
        v->clear();
    }
    for (auto* v : {&lx_, &ux_, &row_scale_, &work_}) {
        v->clear();
    }
}

bool LuFactors::extract_umfpack(void* numeric, int n) {
    clear();
    int lnz = 0, unz = 0, n_row = 0, n_col = 0, nz_udiag = 0;
    if (umfpack_di_get_lunz(&lnz, &unz, &n_row, &n_col, &nz_udiag, numeric) != UMFPACK_OK ||
        n_row != n || n_col != n || nz_udiag != n) {
        return false;
    }
    lp_.resize(static_cast<std::size_t>(n) + 1);
    lj_.resize(static_cast<std::size_t>(lnz));
    lx_.resize(static_cast<std::size_t>(lnz));
    up_.resize(static_cast<std::size_t>(n) + 1);
    ui_.resize(static_cast<std::size_t>(unz));
    ux_.resize(static_cast<std::size_t>(unz));
    p_.resize(static_cast<std::size_t>(n));
    q_.resize(static_cast<std::size_t>(n));
    row_scale_.resize(static_cast<std::size_t>(n));
    int do_recip = 0;
    if (umfpack_di_get_numeric(lp_.data(), lj_.data(), lx_.data(), up_.data(), ui_.data(),
                               ux_.data(), p_.data(), q_.data(), nullptr, &do_recip,
                               row_scale_.data(), numeric) != UMFPACK_OK) {
        clear();
        return false;
    }
    // R scales A's rows; store it as a factor to multiply by.
    if (!do_recip) {
        for (double& r : row_scale_) {
            r = 1.0 / r;
        }
    }
    work_.resize(static_cast<std::size_t>(n));
    n_ = n;
    return true;
}

void LuFactors::solve(const double* b, double* x) const {
    const int n = n_;
    double* z = work_.data();
    // A = R^-1 P^T L U Q^T, so x = Q U^-1 L^-1 P R b.
    for (int k = 0; k < n; ++k) {
        const int i = p_[static_cast<std::size_t>(k)];
        z[k] = b[i] * row_scale_[static_cast<std::size_t>(i)];
    }
    // L z = y by rows: each row's entries left of the unit diagonal (its last entry).
    for (int k = 0; k < n; ++k) {
        double s = z[k];
        const int end = lp_[static_cast<std::size_t>(k) + 1] - 1;
        for (int p = lp_[static_cast<std::size_t>(k)]; p < end; ++p) {
            s -= lx_[static_cast<std::size_t>(p)] * z[lj_[static_cast<std::size_t>(p)]];
        }
        z[k] = s;
    }
    // U w = z by columns, last to first: the diagonal is each column's last entry.
    for (int k = n - 1; k >= 0; --k) {
        const int begin = up_[static_cast<std::size_t>(k)];
        const int diag = up_[static_cast<std::size_t>(k) + 1] - 1;
        const double w = z[k] / ux_[static_cast<std::size_t>(diag)];
        z[k] = w;
        for (int p = begin; p < diag; ++p) {
            z[ui_[static_cast<std::size_t>(p)]] -= ux_[static_cast<std::size_t>(p)] * w;
        }
    }
    for (int k = 0; k < n; ++k) {
        x[q_[static_cast<std::size_t>(k)]] = z[k];
    }
}

} // namespace ifsim::fem
