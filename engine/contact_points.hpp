#pragma once
// Contact points of one interface model (a continuum model M used through Algorithm 1) in
// structure-of-arrays storage.
//
// Per point (columns of padded length P):
//   inputs    t_N, k_N (= d t_N / d g_N, the penalty while in contact), dg1, dg2 (tangential
//             gap increments, Eq. A13), s_p1, s_p2 (extrapolated continuum stress in the local
//             frame, Eqs. 14-16), frame n, t1, t2 (global components, 3 columns each)
//   state     committed and trial: the model state in local axes (interface stress of Eq. 17
//             and e, h / alpha, z, ...), then eps_N, eps_p1, eps_p2, gamma1, gamma2 and the last
//             adaptive sub-increment size
//   outputs   local traction (t_N, tau1, tau2), the Jacobian columns d t_local / d u for the
//             slave displacements (ndim columns) then the master displacements (ndim columns),
//             status and counters
//
// The perturbed evaluations of Eq. 37 are lanes of their own: a point expands into L lanes
// (engine/contact_update.hpp, ContactLaneBlocks) in a lane buffer of length L * P that is
// allocated once and reused every increment.

#include <cstddef>

#include "engine/column_store.hpp"
#include "kernels/interface_settings.hpp"

namespace ifsim {

namespace contact_col {
// inputs
inline constexpr int t_N = 0, k_N = 1, dg1 = 2, dg2 = 3, s_p1 = 4, s_p2 = 5;
inline constexpr int n = 6, t1 = 9, t2 = 12; // frame vectors, 3 columns each
// d s_p / d t_N of the caller's in-plane targets (0 when they do not follow t_N; e.g. targets
// bounded by a multiple of t_N): the normal perturbation lanes move s_p with t_N.
inline constexpr int dsp1_dtn = 15, dsp2_dtn = 16;
// > 0: the base lane takes exactly this many equal sub-increments (a frozen discretisation, for
// a caller whose Newton stalls on the step selection's noise); 0: its own control.
inline constexpr int forced = 17;
inline constexpr int n_inputs = 18;
// outputs
inline constexpr int traction = 0; // t_N, tau1, tau2
inline constexpr int jacobian = 3; // 3 * (2 ndim) columns: comp + 3 * column
inline constexpr int status = 21, subincrements = 22, newton_iterations = 23, evaluations = 24,
                     model_substeps = 25, residual = 26, open = 27, cause = 28, band_clamped = 29,
                     dropped_columns = 30,
                     newton_fallbacks = 31; // lanes that took Algorithm 1's second try
inline constexpr int n_outputs = 32;
} // namespace contact_col

// Extra state entries after the model state.
namespace contact_state {
inline constexpr int eps_n = 0, eps_p1 = 1, eps_p2 = 2, gamma1 = 3, gamma2 = 4, last_sub = 5;
inline constexpr int n_extra = 6;
} // namespace contact_state

template <class M>
class ContactPoints {
public:
    static constexpr int NS = M::n_state;
    static constexpr int n_state_cols = NS + contact_state::n_extra;

    ContactPoints(std::size_t n, int ndim)
        : n_(n), p_(padded_size(n)), ndim_(ndim), inputs_(contact_col::n_inputs, p_),
          committed_(n_state_cols, p_), trial_(n_state_cols, p_),
          outputs_(contact_col::n_outputs, p_) {
        // Padding points: a valid isotropic state in contact, no shear increment.
        for (std::size_t i = 0; i < p_; ++i) {
            for (int k = 0; k < 3; ++k) {
                committed_.col(k)[i] = -100.0;
            }
            committed_.col(6)[i] = 0.7;
            inputs_.col(contact_col::t_N)[i] = -100.0;
            inputs_.col(contact_col::s_p1)[i] = -100.0;
            inputs_.col(contact_col::s_p2)[i] = -100.0;
            inputs_.col(contact_col::n + 0)[i] = 1.0;
            inputs_.col(contact_col::t1 + 1)[i] = 1.0;
            inputs_.col(contact_col::t2 + 2)[i] = 1.0;
        }
        trial_ = committed_;
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
            inputs_.col(contact_col::n + d)[i] = n[d];
            inputs_.col(contact_col::t1 + d)[i] = t1[d];
            inputs_.col(contact_col::t2 + d)[i] = t2[d];
        }
    }

    // Accept the trial state (swap, not copy).
    void commit() { committed_.swap(trial_); }

    // Start-of-life state of point i: model state in local axes, zero interface strains.
    void set_state(std::size_t i, const StateVec<double, NS>& y) {
        for (int k = 0; k < NS; ++k) {
            committed_.col(k)[i] = y[k];
            trial_.col(k)[i] = y[k];
        }
        for (int k = NS; k < n_state_cols; ++k) {
            committed_.col(k)[i] = 0.0;
            trial_.col(k)[i] = 0.0;
        }
    }

private:
    std::size_t n_;
    std::size_t p_;
    int ndim_;
    ColumnStore inputs_;
    ColumnStore committed_;
    ColumnStore trial_;
    ColumnStore outputs_;
};

} // namespace ifsim
