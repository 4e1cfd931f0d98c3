#include "fem/lu_factors.hpp"

#include <algorithm>
#include <numeric>
#include <tuple>

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

// One factor in runs: `line` k (a row of L, a column of U) holds runs [line[k], line[k + 1]).
struct Runs {
    std::vector<int>* line;
    std::vector<int>* first;
    std::vector<int>* value;
};

// Cuts each line of a compressed factor (pointers p, indices i, values x, as UMFPACK returns
// them: sorted, the diagonal last) into runs of consecutive indices, leaving the diagonal out,
// and copies the values in line order to `out`.
template <class Real>
void build_runs(int n, const std::vector<int>& p, const std::vector<int>& idx,
                const std::vector<double>& x, Runs runs, std::vector<Real>& out) {
    runs.line->resize(static_cast<std::size_t>(n) + 1);
    runs.first->clear();
    runs.value->clear();
    out.resize(idx.size() - static_cast<std::size_t>(n));
    std::size_t o = 0;
    for (int k = 0; k < n; ++k) {
        (*runs.line)[static_cast<std::size_t>(k)] = static_cast<int>(runs.first->size());
        const int end = p[static_cast<std::size_t>(k) + 1] - 1;
        for (int q = p[static_cast<std::size_t>(k)]; q < end; ++q, ++o) {
            const int i = idx[static_cast<std::size_t>(q)];
            if (q == p[static_cast<std::size_t>(k)] ||
                i != idx[static_cast<std::size_t>(q) - 1] + 1) {
                runs.first->push_back(i);
                runs.value->push_back(static_cast<int>(o));
            }
            out[o] = static_cast<Real>(x[static_cast<std::size_t>(q)]);
        }
    }
    (*runs.line)[static_cast<std::size_t>(n)] = static_cast<int>(runs.first->size());
    runs.value->push_back(static_cast<int>(o));
}

// sum_t v[t] z[t] over a run, in eight interleaved partial sums (a fixed order: the same bits
// on every call) that the compiler keeps in vector registers.
template <class Real>
inline double run_dot(const Real* v, const double* z, int len) {
    double s[8] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    int t = 0;
    for (; t + 8 <= len; t += 8) {
        for (int u = 0; u < 8; ++u) {
            s[u] += static_cast<double>(v[t + u]) * z[t + u];
        }
    }
    for (; t < len; ++t) {
        s[0] += static_cast<double>(v[t]) * z[t];
    }
    return ((s[0] + s[4]) + (s[1] + s[5])) + ((s[2] + s[6]) + (s[3] + s[7]));
}

// z[t] -= v[t] w over a run.
template <class Real>
inline void run_axpy(const Real* v, double w, double* z, int len) {
    for (int t = 0; t < len; ++t) {
        z[t] -= static_cast<double>(v[t]) * w;
    }
}

} // namespace

void LuFactors::clear() {
    n_ = 0;
    split_ = 0;
    lval_count_ = uval_count_ = 0;
    for (auto* v : {&lrow_, &lrun_first_, &lrun_value_, &ucol_, &urun_first_, &urun_value_, &p_,
                    &q_, &sets_[0], &sets_[1]}) {
        v->clear();
    }
    for (auto* v : {&lx_, &ux_, &udiag_, &row_scale_, &work_}) {
        v->clear();
    }
    lx_s_.clear();
    ux_s_.clear();
    set_nonzeros_ = {0, 0};
    serial_nonzeros_ = 0;
}

bool LuFactors::extract_umfpack(void* numeric, int n, bool two_sets, LuPrecision precision) {
    clear();
    int lnz = 0, unz = 0, n_row = 0, n_col = 0, nz_udiag = 0;
    if (umfpack_di_get_lunz(&lnz, &unz, &n_row, &n_col, &nz_udiag, numeric) != UMFPACK_OK ||
        n_row != n || n_col != n || nz_udiag != n) {
        return false;
    }
    p_.resize(static_cast<std::size_t>(n));
    q_.resize(static_cast<std::size_t>(n));
    row_scale_.resize(static_cast<std::size_t>(n));
    udiag_.resize(static_cast<std::size_t>(n));
    // L (with P and R) and U (with Q and U's diagonal) are copied out by two calls, side by
    // side: UMFPACK does not modify the numeric object and gives each call its own workspace.
    int do_recip = 0;
    bool l_ok = false, u_ok = false;
    auto size_scratch = [n](std::vector<int>& ptr, std::vector<int>& idx, std::vector<double>& x,
                            int nz) {
        ptr.resize(static_cast<std::size_t>(n) + 1);
        idx.resize(static_cast<std::size_t>(nz));
        x.resize(static_cast<std::size_t>(nz));
    };
    auto cut = [&](const std::vector<int>& ptr, const std::vector<int>& idx,
                   const std::vector<double>& x, Runs runs, std::vector<double>& values,
                   std::vector<float>& values_single) {
        if (precision == LuPrecision::single_precision) {
            build_runs(n, ptr, idx, x, runs, values_single);
        } else {
            build_runs(n, ptr, idx, x, runs, values);
        }
    };
    Scratch& w = scratch_;
    tbb::parallel_invoke(
        [&] {
            size_scratch(w.lp, w.lj, w.lx, lnz);
            l_ok = umfpack_di_get_numeric(w.lp.data(), w.lj.data(), w.lx.data(), nullptr, nullptr,
                                          nullptr, p_.data(), nullptr, nullptr, &do_recip,
                                          row_scale_.data(), numeric) == UMFPACK_OK;
            if (l_ok) {
                cut(w.lp, w.lj, w.lx, {&lrow_, &lrun_first_, &lrun_value_}, lx_, lx_s_);
            }
        },
        [&] {
            size_scratch(w.up, w.ui, w.ux, unz);
            u_ok = umfpack_di_get_numeric(nullptr, nullptr, nullptr, w.up.data(), w.ui.data(),
                                          w.ux.data(), nullptr, q_.data(), udiag_.data(), nullptr,
                                          nullptr, numeric) == UMFPACK_OK;
            if (u_ok) {
                cut(w.up, w.ui, w.ux, {&ucol_, &urun_first_, &urun_value_}, ux_, ux_s_);
            }
        });
    if (!l_ok || !u_ok) {
        clear();
        return false;
    }
    // R scales A's rows; store it as a factor to multiply by.
    if (!do_recip) {
        for (double& r : row_scale_) {
            r = 1.0 / r;
        }
    }
    lval_count_ = precision == LuPrecision::single_precision ? lx_s_.size() : lx_.size();
    uval_count_ = precision == LuPrecision::single_precision ? ux_s_.size() : ux_.size();
    precision_ = precision;
    work_.resize(static_cast<std::size_t>(n));
    n_ = n;
    serial_nonzeros_ = nonzeros();
    if (two_sets) {
        find_two_sets();
    }
    return true;
}

long LuFactors::entries_of_pivot(int k) const {
    const auto sk = static_cast<std::size_t>(k);
    return static_cast<long>(lrun_value_[static_cast<std::size_t>(lrow_[sk + 1])] -
                             lrun_value_[static_cast<std::size_t>(lrow_[sk])] +
                             urun_value_[static_cast<std::size_t>(ucol_[sk + 1])] -
                             urun_value_[static_cast<std::size_t>(ucol_[sk])]) +
           1;
}

// Calls visit(first, length) for every run of pivots j < k that pivot k's row of L or column
// of U refers to.
template <class Visit>
void LuFactors::for_each_run(int k, const Visit& visit) const {
    const auto sk = static_cast<std::size_t>(k);
    for (const auto& [line, first, value] :
         {std::tie(lrow_, lrun_first_, lrun_value_), std::tie(ucol_, urun_first_, urun_value_)}) {
        for (int r = line[sk]; r < line[sk + 1]; ++r) {
            const auto sr = static_cast<std::size_t>(r);
            visit(first[sr], value[sr + 1] - value[sr]);
        }
    }
}

// Chooses the split that minimises the estimated two-thread cost max(larger set, half the
// prefix) + rest, over the sets of the prefix linked by entries of L (row k, column j < k) or
// U (row i < k, column k); then deals the prefix's sets out largest first to the lighter side.
//
// Pivot k linked to every pivot of a run [a, a + len) joins the same sets as the run chained
// pivot to next pivot and k linked to a. A chain link between j and j + 1 is made once per
// copy (`next_unchained` skips the made ones), so the sets cost one union per run, not one
// per factor entry.
void LuFactors::find_two_sets() {
    const int n = n_;
    struct Linker {
        Sets sets;
        std::vector<int> next_unchained; // j, or a later pivot: j + 1 ... chained already
        explicit Linker(int n) : sets(n), next_unchained(static_cast<std::size_t>(n)) {
            std::iota(next_unchained.begin(), next_unchained.end(), 0);
        }
        int skip(int j) {
            while (next_unchained[static_cast<std::size_t>(j)] != j) {
                const int up = next_unchained[static_cast<std::size_t>(
                    next_unchained[static_cast<std::size_t>(j)])];
                next_unchained[static_cast<std::size_t>(j)] = up;
                j = up;
            }
            return j;
        }
        void chain(int a, int last) {
            for (int j = skip(a); j < last; j = skip(j)) {
                sets.join(j, j + 1);
                next_unchained[static_cast<std::size_t>(j)] = j + 1;
            }
        }
    };
    auto link_to_prefix = [&](Linker& l, int k) {
        for_each_run(k, [&](int a, int len) {
            l.chain(a, a + len - 1);
            l.sets.join(k, a);
        });
        return l.sets.weight[static_cast<std::size_t>(l.sets.root(k))];
    };
    const long total = nonzeros();
    long best_cost = total;
    int best_split = 0;
    {
        Linker l(n);
        long prefix = 0, largest = 0;
        for (int k = 0; k < n; ++k) {
            l.sets.weight[static_cast<std::size_t>(k)] = entries_of_pivot(k);
            prefix += entries_of_pivot(k);
            largest = std::max(largest, link_to_prefix(l, k));
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
    Linker l(n);
    Sets& s = l.sets;
    for (int k = 0; k < best_split; ++k) {
        s.weight[static_cast<std::size_t>(k)] = entries_of_pivot(k);
        link_to_prefix(l, k);
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

// L z = y, row k: its runs left of the unit diagonal.
template <class Real>
void LuFactors::forward_row(int k, const Real* lx, double* z) const {
    double s = z[k];
    for (int r = lrow_[static_cast<std::size_t>(k)]; r < lrow_[static_cast<std::size_t>(k) + 1];
         ++r) {
        const int v = lrun_value_[static_cast<std::size_t>(r)];
        s -= run_dot(lx + v, z + lrun_first_[static_cast<std::size_t>(r)],
                     lrun_value_[static_cast<std::size_t>(r) + 1] - v);
    }
    z[k] = s;
}

// U w = z, column k (all later columns done).
template <class Real>
void LuFactors::backward_column(int k, const Real* ux, double* z) const {
    const double w = z[k] / udiag_[static_cast<std::size_t>(k)];
    z[k] = w;
    for (int r = ucol_[static_cast<std::size_t>(k)]; r < ucol_[static_cast<std::size_t>(k) + 1];
         ++r) {
        const int v = urun_value_[static_cast<std::size_t>(r)];
        run_axpy(ux + v, w, z + urun_first_[static_cast<std::size_t>(r)],
                 urun_value_[static_cast<std::size_t>(r) + 1] - v);
    }
}

template <class Real>
void LuFactors::solve_with(const Real* lx, const Real* ux, double* z) const {
    const int n = n_;
    if (split_ > 0) {
        tbb::parallel_invoke(
            [&] {
                for (int k : sets_[0]) {
                    forward_row(k, lx, z);
                }
            },
            [&] {
                for (int k : sets_[1]) {
                    forward_row(k, lx, z);
                }
            });
    }
    for (int k = split_; k < n; ++k) {
        forward_row(k, lx, z);
    }
    for (int k = n - 1; k >= split_; --k) {
        backward_column(k, ux, z);
    }
    if (split_ > 0) {
        tbb::parallel_invoke(
            [&] {
                for (auto it = sets_[0].rbegin(); it != sets_[0].rend(); ++it) {
                    backward_column(*it, ux, z);
                }
            },
            [&] {
                for (auto it = sets_[1].rbegin(); it != sets_[1].rend(); ++it) {
                    backward_column(*it, ux, z);
                }
            });
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
    if (precision_ == LuPrecision::single_precision) {
        solve_with(lx_s_.data(), ux_s_.data(), z);
    } else {
        solve_with(lx_.data(), ux_.data(), z);
    }
    for (int k = 0; k < n; ++k) {
        x[q_[static_cast<std::size_t>(k)]] = z[k];
    }
}

} // namespace ifsim::fem
