#pragma once
// Contact points with Coulomb friction (kernels/coulomb.hpp) in structure-of-arrays storage,
// and their batched update: the cheap interface model for smooth surfaces (paper §6.1), with
// its exact analytical Jacobian, so one lane per point (no Eq. 37 perturbations).
//
// Per point (columns of padded length P):
//   inputs    t_N, k_N (= d t_N / d g_N, the normal penalty), dg1, dg2 (tangential gap
//             increments, Eq. A13), frame n, t1, t2 (global components, 3 columns each)
//   state     committed and trial tangential traction tau1, tau2
//   outputs   the layout of ContactPoints' outputs (engine/contact_points.hpp): local traction
//             (t_N, tau1, tau2) at contact_col::traction, the Jacobian columns d t_local / d u
//             for the slave then the master displacements at contact_col::jacobian; then the
//             slip and open flags (1 or 0)
// Batched like the contact engine: TBB runs fixed chunks of points, xsimd runs across points
// inside a chunk, so results do not depend on the thread count.

#include <cstddef>

#include "engine/column_store.hpp"
#include "engine/contact_points.hpp"
#include "engine/parallel_chunks.hpp"
#include "kernels/coulomb.hpp"

namespace ifsim {

namespace coulomb_col {
// inputs
inline constexpr int t_N = 0, k_N = 1, dg1 = 2, dg2 = 3;
inline constexpr int n = 4, t1 = 7, t2 = 10; // frame vectors, 3 columns each
inline constexpr int n_inputs = 13;
// state
inline constexpr int tau1 = 0, tau2 = 1;
inline constexpr int n_state = 2;
// outputs after the traction and Jacobian columns of contact_col
inline constexpr int slipping = contact_col::status, open = contact_col::status + 1;
inline constexpr int n_outputs = open + 1;
} // namespace coulomb_col

class CoulombContactPoints {
public:
    CoulombContactPoints(std::size_t n, int ndim)
        : n_(n), p_(padded_size(n)), ndim_(ndim), inputs_(coulomb_col::n_inputs, p_),
          committed_(coulomb_col::n_state, p_), trial_(coulomb_col::n_state, p_),
          outputs_(coulomb_col::n_outputs, p_) {
        // Padding points: in contact, no motion, a valid frame.
        for (std::size_t i = 0; i < p_; ++i) {
            inputs_.col(coulomb_col::t_N)[i] = -100.0;
            inputs_.col(coulomb_col::n + 0)[i] = 1.0;
            inputs_.col(coulomb_col::t1 + 1)[i] = 1.0;
            inputs_.col(coulomb_col::t2 + 2)[i] = 1.0;
        }
    }

    std::size_t size() const { return n_; }
    std::size_t padded() const { return p_; }
    int ndim() const { return ndim_; }

    double* input(int k) { return inputs_.col(k); }
    const double* input(int k) const { return inputs_.col(k); }
    double* committed(int k) { return committed_.col(k); }
    const double* committed(int k) const { return committed_.col(k); }
    double* trial(int k) { return trial_.col(k); }
    const double* trial(int k) const { return trial_.col(k); }
    double* output(int k) { return outputs_.col(k); }
    const double* output(int k) const { return outputs_.col(k); }

    // Jacobian entry d t_comp / d u: column c in [0, ndim) slave, [ndim, 2 ndim) master.
    double jacobian(std::size_t i, int comp, int c) const {
        return outputs_.col(contact_col::jacobian + comp + 3 * c)[i];
    }

    void set_frame(std::size_t i, const double n[3], const double t1[3], const double t2[3]) {
        for (int d = 0; d < 3; ++d) {
            inputs_.col(coulomb_col::n + d)[i] = n[d];
            inputs_.col(coulomb_col::t1 + d)[i] = t1[d];
            inputs_.col(coulomb_col::t2 + d)[i] = t2[d];
        }
    }

    // Committed tangential traction of point i (the start of its life, or a restart).
    void set_traction(std::size_t i, double tau1, double tau2) {
        committed_.col(coulomb_col::tau1)[i] = trial_.col(coulomb_col::tau1)[i] = tau1;
        committed_.col(coulomb_col::tau2)[i] = trial_.col(coulomb_col::tau2)[i] = tau2;
    }

    // Accept the trial state (swap, not copy).
    void commit() { committed_.swap(trial_); }

private:
    std::size_t n_;
    std::size_t p_;
    int ndim_;
    ColumnStore inputs_;
    ColumnStore committed_;
    ColumnStore trial_;
    ColumnStore outputs_;
};

struct CoulombContactOptions {
    bool simd = true;
    std::size_t chunk_points = 256; // points per TBB task (rounded up to the lane width)
};

struct CoulombContactReport {
    std::size_t points = 0;
    std::size_t slipping = 0;
    std::size_t open = 0;
    double evaluations = 0.0; // Coulomb updates: one per point
};

namespace detail {

template <class T>
void coulomb_range(CoulombContactPoints& cp, const CoulombParams& p, std::size_t begin,
                   std::size_t end) {
    constexpr std::size_t W = simd::width_v<T>;
    auto load = [](const double* c, std::size_t i) {
        if constexpr (W == 1) {
            return c[i];
        } else {
            return T::load_aligned(c + i);
        }
    };
    auto store = [](double* c, std::size_t i, const T& v) {
        if constexpr (W == 1) {
            c[i] = v;
        } else {
            v.store_aligned(c + i);
        }
    };
    const int ndim = cp.ndim();
    for (std::size_t i = begin; i < end; i += W) {
        const T t_N = load(cp.input(coulomb_col::t_N), i);
        const auto r = coulomb_update<T>(p, t_N, load(cp.committed(coulomb_col::tau1), i),
                                         load(cp.committed(coulomb_col::tau2), i),
                                         load(cp.input(coulomb_col::dg1), i),
                                         load(cp.input(coulomb_col::dg2), i));
        store(cp.trial(coulomb_col::tau1), i, r.tau1);
        store(cp.trial(coulomb_col::tau2), i, r.tau2);
        store(cp.output(contact_col::traction + 0), i, simd::select(r.open, T(0.0), t_N));
        store(cp.output(contact_col::traction + 1), i, r.tau1);
        store(cp.output(contact_col::traction + 2), i, r.tau2);
        store(cp.output(coulomb_col::slipping), i, simd::select(r.slipping, T(1.0), T(0.0)));
        store(cp.output(coulomb_col::open), i, simd::select(r.open, T(1.0), T(0.0)));
        // Gap change per unit displacement (Eq. 7, A13): slave +, master -; the tangential gap
        // increment is dg_T,b = -(delta g . t_b), the normal one delta g . n.
        const T k_N = simd::select(r.open, T(0.0), load(cp.input(coulomb_col::k_N), i));
        for (int side = 0; side < 2; ++side) {
            const double sgn = side == 0 ? 1.0 : -1.0;
            for (int d = 0; d < ndim; ++d) {
                const int c = side * ndim + d;
                const T dgn = sgn * load(cp.input(coulomb_col::n + d), i);
                const T dgt[2] = {-sgn * load(cp.input(coulomb_col::t1 + d), i),
                                  -sgn * load(cp.input(coulomb_col::t2 + d), i)};
                const T dtN = k_N * dgn;
                store(cp.output(contact_col::jacobian + 0 + 3 * c), i, dtN);
                for (int a = 0; a < 2; ++a) {
                    const T v =
                        r.dtau_dtN[a] * dtN + r.dtau_ddg[a][0] * dgt[0] + r.dtau_ddg[a][1] * dgt[1];
                    store(cp.output(contact_col::jacobian + 1 + a + 3 * c), i, v);
                }
            }
        }
    }
}

} // namespace detail

// Trial traction and Jacobian of every point; the state is committed by cp.commit().
inline CoulombContactReport coulomb_contact_update(CoulombContactPoints& cp, const CoulombParams& p,
                                                   const CoulombContactOptions& opt) {
    const std::size_t P = cp.padded();
    const std::size_t chunk = ((opt.chunk_points + simd::lanes - 1) / simd::lanes) * simd::lanes;
    for_chunks(P, chunk, [&](std::size_t b, std::size_t e) {
        if (opt.simd) {
            detail::coulomb_range<simd::batch>(cp, p, b, e);
        } else {
            detail::coulomb_range<double>(cp, p, b, e);
        }
    });

    // Serial reduction in point order: deterministic for any thread count.
    CoulombContactReport rep;
    rep.points = cp.size();
    rep.evaluations = static_cast<double>(cp.size());
    for (std::size_t i = 0; i < cp.size(); ++i) {
        rep.slipping += cp.output(coulomb_col::slipping)[i] > 0.5 ? 1 : 0;
        rep.open += cp.output(coulomb_col::open)[i] > 0.5 ? 1 : 0;
    }
    return rep;
}

} // namespace ifsim
