#pragma once
// A contact pair whose interface is a continuum model (novel or Stutz formulation): the
// gather of the gaps and of the extrapolated continuum stresses (Eqs. 14-16) into the contact
// engine's points, Algorithm 1 with its Eq. 37 lanes, the scatter of tractions and Jacobian
// columns, the bounds and relaxation of the in-plane targets. Internal to the contact pairs
// (made by make_contact_pair, fem/contact_pair.cpp).

#include <algorithm>
#include <cassert>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "engine/contact_update.hpp"
#include "fem/aitken_relaxation.hpp"
#include "fem/contact_pair_base.hpp"

namespace ifsim::fem::detail {

template <class M>
class InterfacePair final : public PairBase {
public:
    InterfacePair(const Mesh& mesh, ContactPairSpec spec, typename M::Params params)
        : PairBase(mesh, std::move(spec)), params_(std::move(params)),
          points_(slave_point_count(mesh, spec_), dim_) {
        if (!spec_.initial_state) {
            throw std::invalid_argument(
                fmt::format("contact pair '{}': no initial interface state", spec_.name));
        }
        if (spec_.options.interface.formulation == InterfaceFormulation::coulomb) {
            throw std::invalid_argument(
                fmt::format("contact pair '{}': Coulomb friction has no continuum interface model",
                            spec_.name));
        }
        spec_.options.interface.ndim = dim_;
        k_lo_ = 1.0 - interface_friction_sine(params_);
        base_only_ = spec_.options;
        base_only_.jacobian = ContactJacobian::analytical;
    }

    bool evaluate(const std::vector<double>& du, std::vector<double>& f_int,
                  std::string& error) override {
        {
            PhaseTimer timer(timers_.gather);
            gather_gaps(du, points_, contact_col::t_N, contact_col::k_N, contact_col::dg1,
                        contact_col::dg2);
            for (std::size_t i = 0; i < kin_->n_points(); ++i) {
                set_targets(i);
            }
            hold_partitions();
        }
        // Deferred Jacobian: the residual needs only the base lanes; the Eq. 37 lanes run when
        // the solver asks for the tangent (not after the residual that converges).
        defer_ = spec_.defer_jacobian && spec_.options.jacobian != ContactJacobian::analytical;
        last_failure_.reset();
        ContactReport rep;
        {
            PhaseTimer timer(timers_.kernels);
            rep = engine_.update(points_, params_, defer_ ? base_only_ : spec_.options);
        }
        note_costliest_call();
        while (!rep.ok() && !probing_ && relax_failed_points()) {
            PhaseTimer timer(timers_.kernels);
            count(rep);
            ++counters_.relaxed_reruns;
            rep = engine_.update(points_, params_, defer_ ? base_only_ : spec_.options);
            note_costliest_call();
        }
        PhaseTimer timer(timers_.scatter);
        count(rep);
        if (!rep.ok()) {
            counters_.failed_evaluations += probing_ ? 0 : 1;
            const std::size_t i = rep.first_failed;
            const ContactKinematics& k = kin_->point(i);
            last_failure_ = record_failed_point(
                points_, i, defer_ ? base_only_ : spec_.options, rep.first_failed_cause,
                rep.first_failed_residual,
                fmt::format("contact pair '{}' point {} at ({:.6g}, {:.6g}, {:.6g})", spec_.name, i,
                            k.x[0], k.x[1], k.x[2]));
            error = fmt::format(
                "{} interface point(s) of contact pair '{}' failed in Algorithm 1, first point "
                "{} at ({:.6g}, {:.6g}, {:.6g}): {}; {}",
                rep.failed, spec_.name, i, k.x[0], k.x[1], k.x[2],
                describe_interface_failure(rep.first_failed_cause, rep.first_failed_residual),
                describe_point(i));
            return false;
        }
        for (std::size_t i = 0; i < kin_->n_points(); ++i) {
            take_traction(points_, i);
            add_slip_viscosity(i);
        }
        kin_->assemble(traction_, f_int, nullptr);
        return true;
    }

    std::optional<FailedContactPoint> last_failure() const override { return last_failure_; }
    std::optional<FailedContactPoint> costliest_call() const override { return costliest_; }
    void forget_failure() override { last_failure_.reset(); }

    void commit() override {
        points_.commit();
        held_count_.assign(held_count_.size(), 0.0); // an evaluation between increments chooses
        for (double l : relax_) {
            counters_.relaxed_point_updates += l < 1.0 ? 1.0 : 0.0;
        }
        count_slip_viscosity(counters_);
    }

private:
    // Keeps the call of the last engine update with the most model substeps if it beats the
    // record (one pass over the points; a copy only for a new record).
    void note_costliest_call() {
        if (probing_) {
            return;
        }
        const double* substeps = points_.output(contact_col::model_substeps);
        std::size_t worst = 0;
        for (std::size_t i = 1; i < kin_->n_points(); ++i) {
            worst = substeps[i] > substeps[worst] ? i : worst;
        }
        if (kin_->n_points() == 0 ||
            (costliest_ && substeps[worst] <= costliest_->model_substeps)) {
            return;
        }
        const ContactKinematics& k = kin_->point(worst);
        costliest_ = record_failed_point(
            points_, worst, defer_ ? base_only_ : spec_.options,
            points_.output(contact_col::cause)[worst], points_.output(contact_col::residual)[worst],
            fmt::format("contact pair '{}' point {} at ({:.6g}, {:.6g}, {:.6g})", spec_.name, worst,
                        k.x[0], k.x[1], k.x[2]));
        costliest_->model_substeps = substeps[worst];
    }

protected:
    bool needs_stress() const override { return true; }

    // Eqs. 19-20 ask the interface to carry the continuum's in-plane stresses next to the
    // contact traction t_N. Where the two come from different places (a free end of the
    // interface, a corner where Eq. 14 extrapolates a steep gradient) the combination can lie
    // outside every state the interface model can reach, and Algorithm 1's Newton cannot meet
    // it. Eq. 13 admits a jump of sigma_p between interface and continuum, so such a point
    // takes in-plane targets between the continuum's and the contact's normal stress, the
    // state of Stutz's normal-contact rule that shear alone limits: target = t_N + lambda
    // (s_p - t_N), lambda halved per failure down to 1/8, then 0; doubled back each increment.
    // Needs the point's t_N input of this evaluation.
    //
    // Before that, every target is held inside the at-rest range of the interface's friction
    // angle, K_lo t_N ... t_N / K_lo with K_lo = 1 - sin(kappa phi_c) (Jaky): at a free corner
    // the extrapolated continuum stress falls far below t_N (K = 0.2 seen), and a band that
    // follows it sits on its limit surface, where every sub-increment of shear strains it
    // further sideways (eps_p1 -> +100 %, eps_N -> -95 %: band collapse). Inside the range the
    // targets are the continuum's, as Eqs. 19-20 state (the shear box keeps 0.5 ... 0.8).
    //
    // Both rules tie the target to t_N; its derivative d s_p / d t_N goes to the engine, whose
    // normal perturbation lanes (Eq. 37) move the target with t_N as the residual does.
    void set_targets(std::size_t i) {
        const double l = relax_.empty() ? 1.0 : relax_[i];
        const double t_N = points_.input(contact_col::t_N)[i];
        for (int c = 1; c <= 2; ++c) {
            double s_p = local_stress_[i][static_cast<std::size_t>(c)];
            double ds_p = 0.0;
            if (t_N < 0.0) {
                const double lo = t_N / k_lo_, hi = k_lo_ * t_N; // lo < hi < 0
                ds_p = s_p < lo ? 1.0 / k_lo_ : s_p > hi ? k_lo_ : 0.0;
                s_p = std::clamp(s_p, lo, hi);
            }
            const bool relaxed = l < 1.0;
            points_.input(contact_col::s_p1 + c - 1)[i] = relaxed ? t_N + l * (s_p - t_N) : s_p;
            points_.input(contact_col::dsp1_dtn + c - 1)[i] = relaxed ? 1.0 - l + l * ds_p : ds_p;
        }
    }

    // Lowers lambda of every point that failed in Algorithm 1 (novel formulation only); false
    // when no failed point can be relaxed further (the failure is a true dead end).
    bool relax_failed_points() {
        if (spec_.options.interface.formulation != InterfaceFormulation::novel) {
            return false;
        }
        relax_.resize(kin_->n_points(), 1.0);
        bool any = false;
        for (std::size_t i = 0; i < kin_->n_points(); ++i) {
            if (points_.output(contact_col::status)[i] > -0.5 || relax_[i] <= 0.0 || open(i)) {
                continue; // relaxing the targets of an open point would change nothing
            }
            relax_[i] = relax_[i] > 0.2 ? 0.5 * relax_[i] : 0.0;
            calm_.resize(relax_.size(), 0);
            calm_[i] = 0;
            set_targets(i);
            any = true;
        }
        return any;
    }

    // A point that needed relaxing sits at a lasting feature (a free end, a corner): lambda
    // grows back only after `calm_increments` attempts in a row without a failure there, since
    // each return towards the inadmissible targets strains the interface laterally (ratchet).
    double regather(const ElementStresses& stresses) override {
        if (spec_.options.interface.formulation != InterfaceFormulation::novel) {
            return 0.0;
        }
        targets_before_gather_ = local_stress_;
        const std::vector<Voigt6>& before = targets_before_gather_;
        extrapolate(stresses);
        double change = 0.0;
        for (std::size_t i = 0; i < before.size(); ++i) {
            if (!kin_->point(i).active || open(i)) {
                continue; // an open point does not use the continuum's in-plane stresses
            }
            for (std::size_t c = 1; c <= 2; ++c) {
                const double ref = std::max({std::abs(before[i][c]), 1.0});
                change = std::max(change, std::abs(local_stress_[i][c] - before[i][c]) / ref);
            }
        }
        return change;
    }

    void restore_targets() override {
        // Only right after regather (the same pairing): the copy is dropped once used. A pair
        // whose regather changed nothing (not the novel formulation) holds none.
        if (targets_before_gather_.empty()) {
            return;
        }
        assert(targets_before_gather_.size() == local_stress_.size());
        local_stress_.swap(targets_before_gather_);
        targets_before_gather_.clear();
    }

    void relax_targets() override {
        if (targets_before_gather_.size() != local_stress_.size()) {
            return;
        }
        // The residual G(x) - x of the in-plane targets of the closed points, in a fixed order.
        residual_.clear();
        for (std::size_t i = 0; i < local_stress_.size(); ++i) {
            if (!kin_->point(i).active || open(i)) {
                continue;
            }
            for (std::size_t c = 1; c <= 2; ++c) {
                residual_.push_back(local_stress_[i][c] - targets_before_gather_[i][c]);
            }
        }
        const double omega = aitken_.factor(residual_);
        for (std::size_t i = 0; i < local_stress_.size(); ++i) {
            if (!kin_->point(i).active || open(i)) {
                continue;
            }
            for (std::size_t c = 1; c <= 2; ++c) {
                const double x = targets_before_gather_[i][c];
                local_stress_[i][c] = x + omega * (local_stress_[i][c] - x);
            }
        }
    }

    // t_N of the last evaluation above -open_threshold: the band runs on its own targets.
    bool open(std::size_t i) const {
        return points_.input(contact_col::t_N)[i] > -spec_.options.interface.open_threshold;
    }

    void new_increment() override {
        aitken_.reset();
        held_count_.assign(held_count_.size(), 0.0);
        calm_.resize(relax_.size(), 0);
        for (std::size_t i = 0; i < relax_.size(); ++i) {
            if (relax_[i] >= 1.0 || ++calm_[i] < calm_increments) {
                continue;
            }
            relax_[i] = relax_[i] > 0.0 ? std::min(1.0, 2.0 * relax_[i]) : 0.125;
            calm_[i] = 0;
        }
    }
    static constexpr int calm_increments = 50;

    // The failed point's inputs and committed state, enough to replay it at point level.
    std::string describe_point(std::size_t i) const {
        constexpr int NS = M::n_state;
        const auto in = [&](int c) { return points_.input(c)[i]; };
        const auto st = [&](int c) { return points_.committed(c)[i]; };
        return fmt::format(
            "inputs t_N {:.6g} kPa, s_p1 {:.6g}, s_p2 {:.6g} kPa, dg_T ({:.6g}, {:.6g}) m; "
            "committed interface stress [N, p1, p2, t1, t2] = [{:.6g}, {:.6g}, {:.6g}, {:.6g}, "
            "{:.6g}] kPa, void ratio {:.6g}, eps_N {:.6g}, eps_p1 {:.6g}, eps_p2 {:.6g}",
            in(contact_col::t_N), in(contact_col::s_p1), in(contact_col::s_p2),
            in(contact_col::dg1), in(contact_col::dg2), st(0), st(1), st(2), st(3), st(4),
            st(state_index::void_ratio), st(NS + contact_state::eps_n),
            st(NS + contact_state::eps_p1), st(NS + contact_state::eps_p2));
    }

    // The same update with the Jacobian lanes: the base lanes repeat the residual's
    // evaluation exactly (same inputs, lane arithmetic independent of the batch), the perturbed
    // lanes give the columns. A perturbed run cannot fail where the base did not (a failed
    // perturbed lane only drops its column).
    void refresh_jacobian() override {
        if (!defer_) {
            return;
        }
        defer_ = false;
        ContactReport rep;
        {
            PhaseTimer timer(timers_.kernels);
            rep = engine_.update(points_, params_, spec_.options);
        }
        PhaseTimer timer(timers_.scatter);
        count(rep);
        for (std::size_t i = 0; i < kin_->n_points(); ++i) {
            take_traction(points_, i);
            add_slip_viscosity(i);
        }
    }

    bool holds_partition() const {
        return spec_.hold_partition && spec_.options.interface.adaptive;
    }

    // The base lanes' sub-increments of this evaluation: the held ones, or (none held yet)
    // the error control's.
    void hold_partitions() {
        const std::size_t n = kin_->n_points();
        held_count_.resize(n, 0.0);
        held_slip_.resize(2 * n, 0.0);
        const bool hold = holds_partition();
        for (std::size_t i = 0; i < n; ++i) {
            points_.input(contact_col::forced)[i] = hold ? held_count_[i] : 0.0;
        }
    }

    // The slip change since the count was chosen, against its allowance: (regrowth - 1) times
    // the slip it was chosen for, at least the paper's sub-increment (max_subincrement d_s0),
    // so that growth, a reversal and a count chosen at zero slip are all caught.
    bool outgrown(std::size_t i) const {
        const double d1 = points_.input(contact_col::dg1)[i] - held_slip_[2 * i];
        const double d2 = points_.input(contact_col::dg2)[i] - held_slip_[2 * i + 1];
        const InterfaceSettings& is = spec_.options.interface;
        const double floor = is.max_subincrement * is.shear_band_thickness;
        const double chosen = std::hypot(held_slip_[2 * i], held_slip_[2 * i + 1]);
        return std::hypot(d1, d2) > (spec_.partition_regrowth - 1.0) * std::max(chosen, floor);
    }

    // Released only between Newton solves, never inside one: a count that changes between
    // iterations puts a jump into the residual that the solve cannot converge through (the
    // coarse §6 scene, released as soon as the slip grew: Newton stalled at 2.4e-4 in gravity
    // stage 2).
    std::size_t release_outgrown_partitions() override {
        if (!holds_partition()) {
            return 0;
        }
        std::size_t n = 0;
        for (std::size_t i = 0; i < held_count_.size(); ++i) {
            if (held_count_[i] > 0.0 && outgrown(i)) {
                held_count_[i] = 0.0;
                ++n;
            }
        }
        return n;
    }

    // Called by the solver for each iterate its Newton iteration goes on from (the residual it
    // starts from, every accepted line-search step; not rejected trials or probes): points
    // that chose their sub-increments in that evaluation keep the count. Open points (output
    // open = 1: separated, and touching ones between -open_threshold and 0, which run
    // Algorithm 1 at sigma_N = -threshold) are not held: they choose in every evaluation.
    void hold_chosen_partitions() override {
        if (!holds_partition() || probing_ || held_count_.size() != kin_->n_points()) {
            return;
        }
        for (std::size_t i = 0; i < kin_->n_points(); ++i) {
            const double count = points_.output(contact_col::subincrements)[i];
            if (held_count_[i] == 0.0 && count > 0.0 &&
                points_.output(contact_col::open)[i] < 0.5) {
                held_count_[i] = count;
                held_slip_[2 * i] = points_.input(contact_col::dg1)[i];
                held_slip_[2 * i + 1] = points_.input(contact_col::dg2)[i];
            }
        }
    }

    void count(const ContactReport& rep) {
        ++counters_.evaluations;
        counters_.point_updates += static_cast<double>(rep.points);
        counters_.lanes += rep.lanes;
        counters_.subincrements += rep.subincrements;
        counters_.constitutive_evaluations += rep.constitutive_evaluations;
        counters_.model_substeps += rep.model_substeps;
        counters_.interface_newton_iterations += rep.newton_iterations;
        counters_.band_clamped += static_cast<long>(rep.band_clamped);
        counters_.dropped_columns += rep.dropped_columns;
        counters_.newton_fallbacks += rep.newton_fallbacks;
    }

    void start(const std::vector<Voigt6>& local_stress) override {
        constexpr int NS = M::n_state;
        for (std::size_t i = 0; i < points_.size(); ++i) {
            const std::vector<double> y = spec_.initial_state(local_stress[i]);
            if (static_cast<int>(y.size()) != NS) {
                throw std::invalid_argument(fmt::format(
                    "contact pair '{}': the initial interface state has {} values, the model "
                    "needs {}",
                    spec_.name, y.size(), NS));
            }
            StateVec<double, NS> s;
            for (int k = 0; k < NS; ++k) {
                s[k] = y[static_cast<std::size_t>(k)];
            }
            points_.set_state(i, s);
        }
    }

    void add_state_means(std::size_t i, double w, ContactResultant& r) const override {
        constexpr int NS = M::n_state;
        const double eps_n = points_.committed(NS + contact_state::eps_n)[i];
        r.eps_N += w * eps_n;
        r.band_thickness += w * spec_.options.interface.shear_band_thickness * (1.0 + eps_n);
        r.void_ratio += w * points_.committed(state_index::void_ratio)[i];
        r.sigma_p1 += w * points_.committed(1)[i];
        r.sigma_p2 += w * points_.committed(2)[i];
    }

    void add_point_state(std::size_t i, ContactPointRecord& r) const override {
        constexpr int NS = M::n_state;
        r.open = std::max(r.open, points_.output(contact_col::open)[i]);
        r.sigma_p1 = points_.committed(1)[i];
        r.sigma_p2 = points_.committed(2)[i];
        r.eps_N = points_.committed(NS + contact_state::eps_n)[i];
        r.eps_p1 = points_.committed(NS + contact_state::eps_p1)[i];
        r.eps_p2 = points_.committed(NS + contact_state::eps_p2)[i];
        r.band_thickness = band_thickness(spec_.options.interface, r.eps_N); // as sheared at
        r.void_ratio = points_.committed(state_index::void_ratio)[i];
        r.subincrements = points_.output(contact_col::subincrements)[i];
    }

    void save_state(ContactPairSnapshot& s) const override {
        save_columns(points_, ContactPoints<M>::n_state_cols, s);
        s.relax = relax_;
        s.calm.assign(calm_.begin(), calm_.end());
    }
    void load_state(const ContactPairSnapshot& s) override {
        load_columns(points_, ContactPoints<M>::n_state_cols, s);
        relax_ = s.relax;
        calm_.assign(s.calm.begin(), s.calm.end());
    }

private:
    typename M::Params params_;
    ContactOptions base_only_;                       // the spec's options without the Eq. 37 lanes
    bool defer_ = false;                             // the last evaluate() ran the base lanes only
    std::optional<FailedContactPoint> last_failure_; // of the last evaluate()
    std::optional<FailedContactPoint> costliest_;    // costliest_call()
    std::vector<double> relax_; // per point: share lambda of the continuum's in-plane targets
    std::vector<int> calm_;     // per point: increments since its last relaxation
    std::vector<Voigt6> targets_before_gather_; // local_stress_ before the last regather
    AitkenRelaxation aitken_;                   // of the gathers within one increment
    std::vector<double> residual_;              // scratch of relax_targets()
    double k_lo_ = 0.5; // 1 - sin(kappa phi_c): at-rest bounds of the in-plane targets
    // Per point, within the current increment: the equal sub-increments held (0: none yet)
    // and the slip (dg1, dg2) they were chosen for (ContactPairSpec::hold_partition).
    std::vector<double> held_count_, held_slip_;
    ContactPoints<M> points_;
    ContactEngine<M> engine_;
};

} // namespace ifsim::fem::detail
