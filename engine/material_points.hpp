#pragma once
// Material points of one model in structure-of-arrays storage.
//
// Layout (P = size padded to the lane width): one contiguous column of P doubles per state
// entry (model_api.hpp: stress 0..5, e 6, model state 7..), for the committed state and for
// the trial state of the running increment; six columns of strain increments; per-point
// control (fixed substep count, 0 = adaptive) and per-point results (status, substeps,
// rejected substeps, rate evaluations).
//
//   committed: [s11 s11 ... | s22 ... | ... | e ... | h11 ...]   (n_state columns of P)
//   trial:     same shape; update() writes it, commit() swaps it with committed.
//
// Padding points hold a valid isotropic state and a zero increment; they are computed with the
// lanes and never reported.

#include <array>
#include <cstddef>
#include <utility>

#include "engine/aligned.hpp"
#include "kernels/model_api.hpp"

namespace ifsim {

template <class M>
class MaterialPoints {
public:
    static constexpr int n_state = M::n_state;

    explicit MaterialPoints(std::size_t n)
        : n_(n), p_(padded_size(n)), committed_(n_state * p_, 0.0), trial_(n_state * p_, 0.0),
          deps_(6 * p_, 0.0), fixed_substeps_(p_, 0.0), status_(p_, 1.0), substeps_(p_, 0.0),
          rejected_(p_, 0.0), rate_evaluations_(p_, 0.0) {
        // Padding (and not-yet-set points): isotropic compression of 100 kPa, e = 0.7.
        for (std::size_t i = 0; i < p_; ++i) {
            for (int k = 0; k < 3; ++k) {
                committed_[k * p_ + i] = -100.0;
            }
            committed_[6 * p_ + i] = 0.7;
        }
        trial_ = committed_;
    }

    std::size_t size() const { return n_; }
    std::size_t padded() const { return p_; }

    double* committed(int k) { return committed_.data() + k * p_; }
    const double* committed(int k) const { return committed_.data() + k * p_; }
    double* trial(int k) { return trial_.data() + k * p_; }
    const double* trial(int k) const { return trial_.data() + k * p_; }
    double* deps(int j) { return deps_.data() + j * p_; }
    const double* deps(int j) const { return deps_.data() + j * p_; }
    double* fixed_substeps() { return fixed_substeps_.data(); }
    const double* fixed_substeps() const { return fixed_substeps_.data(); }
    double* status() { return status_.data(); }
    const double* status() const { return status_.data(); }
    double* substeps() { return substeps_.data(); }
    const double* substeps() const { return substeps_.data(); }
    double* rejected() { return rejected_.data(); }
    const double* rejected() const { return rejected_.data(); }
    double* rate_evaluations() { return rate_evaluations_.data(); }
    const double* rate_evaluations() const { return rate_evaluations_.data(); }

    void set_state(std::size_t i, const StateVec<double, n_state>& y) {
        for (int k = 0; k < n_state; ++k) {
            committed_[k * p_ + i] = y[k];
            trial_[k * p_ + i] = y[k];
        }
    }
    StateVec<double, n_state> state(std::size_t i) const {
        StateVec<double, n_state> y;
        for (int k = 0; k < n_state; ++k) {
            y[k] = committed_[k * p_ + i];
        }
        return y;
    }
    StateVec<double, n_state> trial_state(std::size_t i) const {
        StateVec<double, n_state> y;
        for (int k = 0; k < n_state; ++k) {
            y[k] = trial_[k * p_ + i];
        }
        return y;
    }
    void set_deps(std::size_t i, const Sym<double>& d) {
        for (int j = 0; j < 6; ++j) {
            deps_[j * p_ + i] = d[j];
        }
    }

    // Accept the trial state of the increment (swap, not copy).
    void commit() { std::swap(committed_, trial_); }

private:
    std::size_t n_;
    std::size_t p_;
    aligned_vector committed_;
    aligned_vector trial_;
    aligned_vector deps_;
    aligned_vector fixed_substeps_;
    aligned_vector status_;
    aligned_vector substeps_;
    aligned_vector rejected_;
    aligned_vector rate_evaluations_;
};

} // namespace ifsim
