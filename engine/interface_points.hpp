#pragma once
// The interface point of the point-level interface shear test as its driver sees it
// (engine/interface_test_driver.cpp): an evaluation at (t_N, dg_T1, dg_T2, s_p1, s_p2) gives
// the shear tractions and their derivatives; commit accepts the trial state. Two kinds: a
// continuum model through Algorithm 1 and the contact engine (novel or Stutz), and Coulomb
// penalty friction with its exact return mapping.

#include <chrono>
#include <optional>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "engine/contact_update.hpp"
#include "engine/interface_test_driver.hpp"
#include "engine/point_evaluator.hpp"
#include "kernels/coulomb.hpp"

namespace ifsim::detail {

using Clock = std::chrono::steady_clock;
inline double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

// What the driver needs of the interface point after an evaluation.
struct InterfaceResponse {
    bool ok = true;
    double cause = 0.0; // interface_failure code when !ok
    double tau[2] = {0.0, 0.0};
    double dtau_dg[2][2] = {{0.0, 0.0}, {0.0, 0.0}}; // d tau_a / d dg_T,b
    double dtau_dtN[2] = {0.0, 0.0};
    double dtau_dsp[2][2] = {{0.0, 0.0}, {0.0, 0.0}}; // d tau_a / d s_p(b+1), novel only
    double residual = 0.0;
    bool has_jacobian = false;  // the d tau fields were computed
    double subincrements = 0.0; // Algorithm 1 sub-increments of the base lane (0: none)
};

// A continuum model used as interface model through Algorithm 1 and the contact engine.
template <class Mi>
class ContinuumInterface {
public:
    static constexpr int NS = Mi::n_state;
    static constexpr double normal_lane_stiffness = 1.0e8; // kPa/m, as an FE penalty
    ContinuumInterface(const typename Mi::Params& p, const std::vector<double>& y0,
                       const ContactOptions& opt, InterfaceTestResult& res)
        : params_(p), opt_(opt), res_(res), points_(1, 3) {
        if (static_cast<int>(y0.size()) != NS) {
            throw std::invalid_argument(fmt::format(
                "interface state of model {} needs {} values, got {}", Mi::name, NS, y0.size()));
        }
        if (opt.interface.formulation == InterfaceFormulation::coulomb) {
            throw std::invalid_argument("Coulomb friction has no continuum interface model");
        }
        StateVec<double, NS> y{};
        std::copy(y0.begin(), y0.end(), y.begin());
        points_.set_state(0, y);
        const double n[3] = {1, 0, 0}, t1[3] = {0, 1, 0}, t2[3] = {0, 0, 1};
        points_.set_frame(0, n, t1, t2);
        // t_N is prescribed by the driver, not a penalty. The slave's normal lane perturbs t_N
        // by k_N theta (at most 1 % of |t_N|, ContactEngine::axis_theta); with k_N = 1 that
        // was 1.5e-8 kPa, far below Algorithm 1's own tolerance on sigma_N = t_N, and the
        // column d tau / d t_N was noise (of order 1e4 instead of 0.1): the step Newton stalled
        // near 1e-4 or moved the wrong way. A penalty as in the FE solver gives the lane the
        // same perturbation as there; the column is divided by it (d t_N = k_N d g_N).
        points_.input(contact_col::k_N)[0] = normal_lane_stiffness;
        base_opt_ = opt;
        base_opt_.jacobian = ContactJacobian::analytical;
    }

    // with_jacobian = false evaluates the base lane alone (tractions and trial state, the same
    // bits as with the Jacobian): the driver asks for the derivatives only where another Newton
    // iteration follows, since the Eq. 37 lanes and the s_p probes cost most of an evaluation.
    // forced_subincrements > 0 takes that many equal sub-increments (a frozen discretisation).
    InterfaceResponse evaluate(double t_N, double dg1, double dg2, double s_p1, double s_p2,
                               bool with_jacobian, double forced_subincrements) {
        InterfaceResponse r;
        r.has_jacobian = with_jacobian;
        points_.input(contact_col::forced)[0] = forced_subincrements; // also for the probes
        if (with_jacobian && opt_.interface.formulation == InterfaceFormulation::novel) {
            // The novel formulation's traction also depends on the extrapolated continuum
            // stress (Eqs. 19-20), which the Eq. 37 lanes do not perturb. At point level the
            // sample is that continuum, so the driver's Newton needs d tau / d s_p too: two
            // single-lane probes (run first; the base evaluation below leaves the trial state).
            probe_opt_ = opt_;
            probe_opt_.jacobian = ContactJacobian::analytical;
            const double sp[2] = {s_p1, s_p2};
            for (int b = 0; b < 2; ++b) {
                const double h = 1.0e-6 * std::max(std::abs(sp[b]), 1.0);
                double q[2] = {sp[0], sp[1]};
                q[b] += h;
                const auto plus = probe(t_N, dg1, dg2, q[0], q[1]);
                q[b] -= 2.0 * h;
                const auto minus = probe(t_N, dg1, dg2, q[0], q[1]);
                for (int a = 0; a < 2; ++a) {
                    r.dtau_dsp[a][b] = (plus[a] - minus[a]) / (2.0 * h);
                }
            }
        }
        points_.input(contact_col::t_N)[0] = t_N;
        points_.input(contact_col::dg1)[0] = dg1;
        points_.input(contact_col::dg2)[0] = dg2;
        points_.input(contact_col::s_p1)[0] = s_p1;
        points_.input(contact_col::s_p2)[0] = s_p2;
        const auto t0 = Clock::now();
        const ContactReport rep = with_jacobian ? engine_.update(points_, params_, opt_)
                                                : base_engine_.update(points_, params_, base_opt_);
        res_.interface_seconds += seconds_since(t0);
        res_.counters.interface_evaluations += rep.constitutive_evaluations;
        res_.counters.constitutive_evaluations += rep.constitutive_evaluations;
        res_.counters.model_substeps += rep.model_substeps;
        res_.counters.interface_newton_fallbacks += rep.newton_fallbacks;
        last_subincrements_ = rep.subincrements;
        last_newton_ = rep.newton_iterations;
        r.ok = rep.ok();
        r.subincrements = rep.subincrements;
        r.cause = rep.first_failed_cause;
        last_band_clamped_ = rep.band_clamped > 0;
        r.residual = points_.output(contact_col::residual)[0];
        if (!r.ok) {
            last_failure_ =
                record_failed_point(points_, 0, with_jacobian ? opt_ : base_opt_, r.cause,
                                    r.residual, "the interface point of the interface test");
        }
        r.tau[0] = points_.output(contact_col::traction + 1)[0];
        r.tau[1] = points_.output(contact_col::traction + 2)[0];
        if (!with_jacobian) {
            return r;
        }
        // Columns: slave e_1 (normal: d/d t_N times k_N), master e_2, e_3 (+dg_T1, +dg_T2).
        for (int a = 0; a < 2; ++a) {
            r.dtau_dtN[a] = points_.jacobian(0, 1 + a, 0) / normal_lane_stiffness;
            for (int b = 0; b < 2; ++b) {
                r.dtau_dg[a][b] = points_.jacobian(0, 1 + a, 3 + 1 + b);
            }
        }
        return r;
    }

    // The last evaluation that failed (the record of its Algorithm 1 call).
    const std::optional<FailedContactPoint>& last_failure() const { return last_failure_; }

    void commit(InterfaceTestResult& res) {
        points_.commit();
        res.counters.band_clamped_steps += last_band_clamped_ ? 1 : 0;
        res.counters.subincrements += last_subincrements_;
        res.counters.interface_newton_iterations += last_newton_;
    }

    // The committed state (model state in local axes, then the interface strains and the last
    // sub-increment size), and its restoration for a resumed run.
    std::vector<double> committed_state() const {
        std::vector<double> out;
        for (int k = 0; k < ContactPoints<Mi>::n_state_cols; ++k) {
            out.push_back(points_.committed(k)[0]);
        }
        return out;
    }
    void restore(const std::vector<double>& state) {
        if (static_cast<int>(state.size()) != ContactPoints<Mi>::n_state_cols) {
            throw std::invalid_argument(fmt::format("resumed interface state of model {} needs {} "
                                                    "values, got {}",
                                                    Mi::name, ContactPoints<Mi>::n_state_cols,
                                                    state.size()));
        }
        for (int k = 0; k < ContactPoints<Mi>::n_state_cols; ++k) {
            points_.committed(k)[0] = state[static_cast<std::size_t>(k)];
            points_.trial(k)[0] = state[static_cast<std::size_t>(k)];
        }
    }

    // Why the band may be unable to meet its normal targets, for a failure message ("" when
    // nothing is known): with the novel formulation, targets outside the interface model's
    // limit surface (for models that say where it is).
    std::string diagnose(double t_N, double s_p1, double s_p2) const {
        if constexpr (requires { Mi::matsuoka_nakai(params_, Sym<double>{}); }) {
            if (opt_.interface.formulation == InterfaceFormulation::novel) {
                const auto ls = Mi::matsuoka_nakai(params_, {t_N, s_p1, s_p2, 0.0, 0.0, 0.0});
                if (ls.outside()) {
                    return fmt::format(
                        "; the band's normal targets (sigma_N, sigma_p1, sigma_p2) = ({:.4g}, "
                        "{:.4g}, {:.4g}) kPa lie outside the interface model's limit surface "
                        "at kappa phi_c = {:.3g} deg (Matsuoka-Nakai I1 I2 / I3 = {:.4g} > "
                        "{:.4g}): the novel formulation (Eqs. 19-20) asks the band to carry "
                        "the continuum's in-plane stresses, which a band this smooth cannot",
                        t_N, s_p1, s_p2, params_.roughness * params_.phi_c * 180.0 / M_PI, ls.value,
                        ls.limit);
                }
            }
        }
        return {};
    }

    void fill(InterfaceRow& row, const InterfaceSettings& s) const {
        const double* y[NS];
        for (int k = 0; k < NS; ++k) {
            y[k] = points_.committed(k);
        }
        row.s_n = y[0][0];
        row.s_p1 = y[1][0];
        row.s_p2 = y[2][0];
        row.e_interface = y[6][0];
        row.eps_n = points_.committed(NS + contact_state::eps_n)[0];
        row.eps_p1 = points_.committed(NS + contact_state::eps_p1)[0];
        row.eps_p2 = points_.committed(NS + contact_state::eps_p2)[0];
        row.gamma1 = points_.committed(NS + contact_state::gamma1)[0];
        row.gamma2 = points_.committed(NS + contact_state::gamma2)[0];
        row.band_thickness = band_thickness(s, row.eps_n); // the thickness sheared at
    }

private:
    std::optional<FailedContactPoint> last_failure_;
    std::array<double, 2> probe(double t_N, double dg1, double dg2, double s_p1, double s_p2) {
        points_.input(contact_col::t_N)[0] = t_N;
        points_.input(contact_col::dg1)[0] = dg1;
        points_.input(contact_col::dg2)[0] = dg2;
        points_.input(contact_col::s_p1)[0] = s_p1;
        points_.input(contact_col::s_p2)[0] = s_p2;
        const auto t0 = Clock::now();
        const ContactReport rep = probe_engine_.update(points_, params_, probe_opt_);
        res_.interface_seconds += seconds_since(t0);
        res_.counters.interface_evaluations += rep.constitutive_evaluations;
        res_.counters.constitutive_evaluations += rep.constitutive_evaluations;
        res_.counters.interface_newton_fallbacks += rep.newton_fallbacks;
        return {points_.output(contact_col::traction + 1)[0],
                points_.output(contact_col::traction + 2)[0]};
    }

    const typename Mi::Params& params_;
    const ContactOptions& opt_;
    ContactOptions probe_opt_;
    ContactEngine<Mi> probe_engine_;
    ContactOptions base_opt_;       // the base lane alone (no Jacobian columns)
    ContactEngine<Mi> base_engine_; // own lane buffer: no reallocation between the two kinds
    InterfaceTestResult& res_;
    ContactPoints<Mi> points_;
    ContactEngine<Mi> engine_;
    double last_subincrements_ = 0.0;
    bool last_band_clamped_ = false;
    double last_newton_ = 0.0;
};

// Coulomb penalty friction: exact return mapping with its analytical derivatives.
class CoulombInterface {
public:
    CoulombInterface(const CoulombParams& p, double tau1, double tau2) : p_(p) {
        tau_[0] = tau1;
        tau_[1] = tau2;
    }
    CoulombInterface(const CoulombParams& p, double tau1, double tau2, InterfaceTestResult& res)
        : CoulombInterface(p, tau1, tau2) {
        res_ = &res;
    }
    InterfaceResponse evaluate(double t_N, double dg1, double dg2, double, double, bool, double) {
        const auto t0 = Clock::now();
        const auto c = coulomb_update<double>(p_, t_N, tau_[0], tau_[1], dg1, dg2);
        if (res_) {
            res_->interface_seconds += seconds_since(t0);
            res_->counters.interface_evaluations += 1.0;
            res_->counters.constitutive_evaluations += 1.0;
        }
        InterfaceResponse r;
        r.has_jacobian = true;
        r.tau[0] = trial_[0] = c.tau1;
        r.tau[1] = trial_[1] = c.tau2;
        for (int a = 0; a < 2; ++a) {
            r.dtau_dtN[a] = c.dtau_dtN[a];
            for (int b = 0; b < 2; ++b) {
                r.dtau_dg[a][b] = c.dtau_ddg[a][b];
            }
        }
        return r;
    }
    // Coulomb friction has no Algorithm 1 call to replay.
    std::optional<FailedContactPoint> last_failure() const { return std::nullopt; }

    void commit(InterfaceTestResult&) {
        tau_[0] = trial_[0];
        tau_[1] = trial_[1];
    }
    std::vector<double> committed_state() const { return {tau_[0], tau_[1]}; }
    void restore(const std::vector<double>& state) {
        if (state.size() != 2) {
            throw std::invalid_argument(fmt::format(
                "resumed Coulomb interface state needs 2 values, got {}", state.size()));
        }
        tau_[0] = trial_[0] = state[0];
        tau_[1] = trial_[1] = state[1];
    }
    std::string diagnose(double, double, double) const { return {}; }
    void fill(InterfaceRow& row, const InterfaceSettings&) const {
        row.s_n = row.t_n;
        row.band_thickness = 0.0;
    }

private:
    CoulombParams p_;
    InterfaceTestResult* res_ = nullptr;
    double tau_[2] = {0.0, 0.0};
    double trial_[2] = {0.0, 0.0};
};

} // namespace ifsim::detail
