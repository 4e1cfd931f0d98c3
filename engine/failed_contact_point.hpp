#pragma once
// One contact point's failed evaluation as Algorithm 1 saw it: the committed state, the inputs
// and the options of the call. Enough to run that evaluation again alone: the replay scene of
// kind "interface-point" (io/replay/interface_replay.hpp) is written from it.

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "engine/contact_points.hpp"
#include "engine/contact_update.hpp"

namespace ifsim {

struct FailedContactPoint {
    std::string model; // the interface model's scene name
    int ndim = 3;
    // The model state in local axes, then eps_N, eps_p1, eps_p2, gamma1, gamma2 and the last
    // adaptive sub-increment size (ContactPoints' committed columns).
    std::vector<double> state;
    std::array<double, contact_col::n_inputs> inputs{};
    ContactOptions options; // as used by the failed call (a deferred Jacobian runs base lanes only)
    double cause = 0.0;     // interface_failure code
    double residual = 0.0;
    std::string where; // the point in words: "contact pair 'wall' point 12 at (0.1, 0.2, 0)"
    double model_substeps = 0.0; // the call's interface-model substeps (costliest-call record)
};

template <class M>
FailedContactPoint record_failed_point(const ContactPoints<M>& cp, std::size_t i,
                                       const ContactOptions& options, double cause, double residual,
                                       std::string where) {
    FailedContactPoint r;
    r.model = M::name;
    r.ndim = cp.ndim();
    for (int k = 0; k < ContactPoints<M>::n_state_cols; ++k) {
        r.state.push_back(cp.committed(k)[i]);
    }
    for (int k = 0; k < contact_col::n_inputs; ++k) {
        r.inputs[static_cast<std::size_t>(k)] = cp.input(k)[i];
    }
    r.options = options;
    r.cause = cause;
    r.residual = residual;
    r.where = std::move(where);
    return r;
}

// The result of running a recorded call again alone (evaluate_contact_point).
struct ContactPointOutcome {
    ContactReport report;
    std::array<double, 3> traction{}; // t_N, tau1, tau2 (local axes)
    std::vector<double> state; // the trial state after the call (FailedContactPoint::state layout)
    double status = 0.0;       // the point's lane status
};

// Runs the call of `point` (state, inputs, options, ndim) for one point with `params`, on the
// SIMD or the scalar path. The call sees exactly what the failed one saw.
template <class M>
ContactPointOutcome evaluate_contact_point(const typename M::Params& params,
                                           const FailedContactPoint& point, bool simd) {
    ContactPoints<M> cp(1, point.ndim);
    for (int k = 0; k < ContactPoints<M>::n_state_cols; ++k) {
        cp.committed(k)[0] = point.state.at(static_cast<std::size_t>(k));
        cp.trial(k)[0] = point.state.at(static_cast<std::size_t>(k));
    }
    for (int k = 0; k < contact_col::n_inputs; ++k) {
        cp.input(k)[0] = point.inputs[static_cast<std::size_t>(k)];
    }
    ContactOptions options = point.options;
    options.simd = simd;
    options.interface.ndim = point.ndim;
    ContactEngine<M> engine;
    ContactPointOutcome out;
    out.report = engine.update(cp, params, options);
    for (int c = 0; c < 3; ++c) {
        out.traction[static_cast<std::size_t>(c)] = cp.output(contact_col::traction + c)[0];
    }
    for (int k = 0; k < ContactPoints<M>::n_state_cols; ++k) {
        out.state.push_back(cp.trial(k)[0]);
    }
    out.status = cp.output(contact_col::status)[0];
    return out;
}

} // namespace ifsim
