#include "fem/lu_factors.hpp"

#include <algorithm>
#include <numeric>

#include <suitesparse/umfpack.h>
#include <tbb/parallel_invoke.h>

namespace ifsim::fem {
namespace {

// Union-find over pivot indices with the factor entries of each set as its weight.
struct Sets {
    std::vector<int> parent;
    std::vector<long> weight;
    explicit Sets(int n) : parent(static_cast<std::size_t>(n)), weight(parent.size(), 0) {
        std::iota(parent.begin(), parent.end(), 0);
    }
    int root(int a) {
        while (parent[static_cast<std::size_t>(a)] != a) {
            const int up = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(a)])];
            parent[static_cast<std::size_t>(a)] = up; // path halving
            a = up;
        }
        return a;
    }
    // Returns the weight of the joined set.
    long join(int a, int b) {
        a = root(a);
        b = root(b);
        if (a == b) {
            return weight[static_cast<std::size_t>(a)];
        }
        if (weight[static_cast<std::size_t>(a)] < weight[static_cast<std::size_t>(b)]) {
            std::swap(a, b);
        }
        parent[static_cast<std::size_t>(b)] = a;
        weight[static_cast<std::size_t>(a)] += weight[static_cast<std::size_t>(b)];
        return weight[static_cast<std::size_t>(a)];
    }
};

} // namespace

void LuFactors::clear() {
    n_ = 0;
    split_ = 0;
    for (auto* v : {&lp_, &lj_, &up_, &ui_, &p_, &q_, &sets_[0], &sets_[1]}) {
        v->clear();
    }
    for (auto* v : {&lx_, &ux_, &row_scale_, &work_}) {
        v->clear();
    }
    set_nonzeros_ = {0, 0};
    serial_nonzeros_ = 0;
}

bool LuFactors::extract_umfpack(void* numeric, int n, bool two_sets) {
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
    serial_nonzeros_ = nonzeros();
    if (two_sets) {
        find_two_sets();
    }
    return true;
}

// Chooses the split that minimises the estimated two-thread cost max(larger set, half the
// prefix) + rest, over the sets of the prefix linked by entries of L (row k, column j < k) or
// U (row i < k, column k); then deals the prefix's sets out largest first to the lighter side.
void LuFactors::find_two_sets() {
    const int n = n_;
    auto entries = [&](int k) {
        return static_cast<long>(
            lp_[static_cast<std::size_t>(k) + 1] - lp_[static_cast<std::size_t>(k)] +
            up_[static_cast<std::size_t>(k) + 1] - up_[static_cast<std::size_t>(k)]);
    };
    auto link_to_prefix = [&](Sets& s, int k) {
        long w = s.weight[static_cast<std::size_t>(s.root(k))];
        for (int p = lp_[static_cast<std::size_t>(k)]; p < lp_[static_cast<std::size_t>(k) + 1] - 1;
             ++p) {
            w = s.join(k, lj_[static_cast<std::size_t>(p)]);
        }
        for (int p = up_[static_cast<std::size_t>(k)]; p < up_[static_cast<std::size_t>(k) + 1] - 1;
             ++p) {
            w = s.join(k, ui_[static_cast<std::size_t>(p)]);
        }
        return w;
    };
    const long total = nonzeros();
    long best_cost = total;
    int best_split = 0;
    {
        Sets s(n);
        long prefix = 0, largest = 0;
        for (int k = 0; k < n; ++k) {
            s.weight[static_cast<std::size_t>(k)] = entries(k);
            prefix += entries(k);
            largest = std::max(largest, link_to_prefix(s, k));
            const long cost = std::max(largest, (prefix + 1) / 2) + (total - prefix);
            if (cost < best_cost) {
                best_cost = cost;
                best_split = k + 1;
            }
        }
    }
    // Not worth a second task below a tenth saved.
    if (10 * best_cost > 9 * total) {
        return;
    }
    Sets s(n);
    for (int k = 0; k < best_split; ++k) {
        s.weight[static_cast<std::size_t>(k)] = entries(k);
        link_to_prefix(s, k);
    }
    std::vector<int> roots;
    for (int k = 0; k < best_split; ++k) {
        if (s.root(k) == k) {
            roots.push_back(k);
        }
    }
    // Largest first, ties by index: a fixed deal for a given factorisation.
    std::sort(roots.begin(), roots.end(), [&](int a, int b) {
        const long wa = s.weight[static_cast<std::size_t>(a)];
        const long wb = s.weight[static_cast<std::size_t>(b)];
        return wa != wb ? wa > wb : a < b;
    });
    std::vector<int> side(static_cast<std::size_t>(n), -1);
    set_nonzeros_ = {0, 0};
    for (int r : roots) {
        const int g = set_nonzeros_[0] <= set_nonzeros_[1] ? 0 : 1;
        side[static_cast<std::size_t>(r)] = g;
        set_nonzeros_[static_cast<std::size_t>(g)] += s.weight[static_cast<std::size_t>(r)];
    }
    for (int k = 0; k < best_split; ++k) {
        sets_[static_cast<std::size_t>(side[static_cast<std::size_t>(s.root(k))])].push_back(k);
    }
    split_ = best_split;
    serial_nonzeros_ = total - set_nonzeros_[0] - set_nonzeros_[1];
}

// L z = y, row k: the entries left of the unit diagonal (its last entry).
void LuFactors::forward_row(int k, double* z) const {
    double s = z[k];
    const int end = lp_[static_cast<std::size_t>(k) + 1] - 1;
    for (int p = lp_[static_cast<std::size_t>(k)]; p < end; ++p) {
        s -= lx_[static_cast<std::size_t>(p)] * z[lj_[static_cast<std::size_t>(p)]];
    }
    z[k] = s;
}

// U w = z, column k (all later columns done): the diagonal is the column's last entry.
void LuFactors::backward_column(int k, double* z) const {
    const int begin = up_[static_cast<std::size_t>(k)];
    const int diag = up_[static_cast<std::size_t>(k) + 1] - 1;
    const double w = z[k] / ux_[static_cast<std::size_t>(diag)];
    z[k] = w;
    for (int p = begin; p < diag; ++p) {
        z[ui_[static_cast<std::size_t>(p)]] -= ux_[static_cast<std::size_t>(p)] * w;
    }
}

void LuFactors::solve(const double* b, double* x) const {
    const int n = n_;
    double* z = work_.data();
    // A = R^-1 P^T L U Q^T, so x = Q U^-1 L^-1 P R b.
    for (int k = 0; k < n; ++k) {
        const int i = p_[static_cast<std::size_t>(k)];
        z[k] = b[i] * row_scale_[static_cast<std::size_t>(i)];
    }
    if (split_ > 0) {
        tbb::parallel_invoke(
            [&] {
                for (int k : sets_[0]) {
                    forward_row(k, z);
                }
            },
            [&] {
                for (int k : sets_[1]) {
                    forward_row(k, z);
                }
            });
    }
    for (int k = split_; k < n; ++k) {
        forward_row(k, z);
    }
    for (int k = n - 1; k >= split_; --k) {
        backward_column(k, z);
    }
    if (split_ > 0) {
        tbb::parallel_invoke(
            [&] {
                for (auto it = sets_[0].rbegin(); it != sets_[0].rend(); ++it) {
                    backward_column(*it, z);
                }
            },
            [&] {
                for (auto it = sets_[1].rbegin(); it != sets_[1].rend(); ++it) {
                    backward_column(*it, z);
                }
            });
    }
    for (int k = 0; k < n; ++k) {
        x[q_[static_cast<std::size_t>(k)]] = z[k];
    }
}

} // namespace ifsim::fem
