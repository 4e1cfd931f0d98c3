#include "fem/contact_pair.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "engine/coulomb_contact.hpp"
#include "fem/mortar_contact.hpp"
#include "fem/phase_timer.hpp"

namespace ifsim::fem {
namespace {

using Vec3 = std::array<double, 3>;

double dot(const Vec3& a, const Vec3& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// The engine's frame of a point: the kinematic frame turned about n so that t1 follows the
// preferred shear direction. t1' = c t1 + s t2, t2' = -s t1 + c t2 (a rotation, so the frame
// keeps its handedness; in 2D c = +-1, s = 0).
struct PointFrame {
    Vec3 n{}, t1{}, t2{};
    double c = 1.0, s = 0.0;

    // Kinematic (dg1, dg2) to the engine frame, and the engine's (tau1, tau2) back.
    std::array<double, 2> to_local(const std::array<double, 2>& v) const {
        return {c * v[0] + s * v[1], -s * v[0] + c * v[1]};
    }
    std::array<double, 2> to_kinematic(double a1, double a2) const {
        return {c * a1 - s * a2, s * a1 + c * a2};
    }
};

PointFrame engine_frame(const ContactKinematics& k, const Vec3& direction, int dim) {
    PointFrame f;
    f.n = k.n;
    const double dn = dot(direction, k.n);
    Vec3 d{direction[0] - dn * k.n[0], direction[1] - dn * k.n[1], direction[2] - dn * k.n[2]};
    if (dim == 2) {
        d[2] = 0.0; // in plane strain t1 stays in the plane
    }
    double c = dot(d, k.t1);
    double s = dim == 2 ? 0.0 : dot(d, k.t2);
    const double len = std::hypot(c, s);
    if (len < 1.0e-12) { // direction normal to the surface: keep the kinematic frame
        c = 1.0;
        s = 0.0;
    } else if (dim == 2) {
        c = c >= 0.0 ? 1.0 : -1.0;
    } else {
        c /= len;
        s /= len;
    }
    f.c = c;
    f.s = s;
    for (std::size_t i = 0; i < 3; ++i) {
        f.t1[i] = c * k.t1[i] + s * k.t2[i];
        f.t2[i] = -s * k.t1[i] + c * k.t2[i];
    }
    return f;
}

// sin(kappa phi_c) of an interface model (paper Eqs. 30, 33).
double interface_friction_sine(const HypoplasticityParams& p) {
    return std::sin(p.roughness * p.phi_c);
}
double interface_friction_sine(const SanisandParams& p) {
    const double phi_c = std::asin(3.0 * p.M_c / (6.0 + p.M_c)); // M_c = 6 sin / (3 - sin)
    return std::sin(p.roughness * phi_c);
}

// Slave integration points: 2-point Gauss per edge (2D), 2x2 per face (3D).
std::size_t slave_point_count(const Mesh& mesh, const ContactPairSpec& spec) {
    return (mesh.dim() == 2 ? 2 : 4) * mesh.face_set(spec.slave_faces).size();
}

std::unique_ptr<MortarKinematics> make_kinematics(const Mesh& mesh, const ContactPairSpec& spec) {
    if (mesh.dim() == 2) {
        return std::make_unique<MortarContact<2>>(mesh, spec.slave_faces, spec.master_faces);
    }
    return std::make_unique<MortarContact<3>>(mesh, spec.slave_faces, spec.master_faces);
}

// What every pair shares: kinematics, engine frames, the penalty with its offsets, and the
// tractions of the last evaluation in the kinematic frame.
class PairBase : public ContactPair {
public:
    PairBase(const Mesh& mesh, ContactPairSpec spec)
        : spec_(std::move(spec)), kin_(make_kinematics(mesh, spec_)), dim_(mesh.dim()) {
        if (!(spec_.normal_penalty > 0.0)) {
            throw std::invalid_argument(
                fmt::format("contact pair '{}': the normal penalty must be positive, got {}",
                            spec_.name, spec_.normal_penalty));
        }
    }

    const ContactPairSpec& spec() const override { return spec_; }
    const MortarKinematics& kinematics() const override { return *kin_; }

    bool begin_increment(const Mesh& mesh, const std::vector<double>& u,
                         const ElementStresses& stresses) override {
        bool changed = false;
        {
            PhaseTimer timer(timers_.search);
            changed = kin_->pair(mesh, u);
        }
        if (kin_->n_points() != slave_point_count(mesh, spec_)) {
            throw std::logic_error("contact kinematics: unexpected number of slave points");
        }
        PhaseTimer timer(timers_.gather);
        const std::size_t n = kin_->n_points();
        frames_.resize(n);
        local_stress_.resize(n);
        for (std::size_t i = 0; i < n; ++i) {
            frames_[i] = engine_frame(kin_->point(i), spec_.shear_direction, dim_);
        }
        if (needs_stress() || (first_ && spec_.prestressed)) {
            extrapolate(stresses);
        }
        if (first_) {
            gap_offset_.assign(n, 0.0);
            for (std::size_t i = 0; i < n && spec_.prestressed; ++i) {
                const ContactKinematics& k = kin_->point(i);
                const double s_nn = local_stress_[i][0];
                if (k.active && s_nn < 0.0) {
                    gap_offset_[i] = k.g_N - s_nn / spec_.normal_penalty;
                }
            }
            start(local_stress_);
            first_ = false;
        }
        traction_.assign(n, {});
        new_increment();
        return changed;
    }

    void add_tangent(std::vector<ContactTriplet>& K) override {
        refresh_jacobian();
        PhaseTimer timer(timers_.scatter);
        scratch_.assign(scratch_.size(), 0.0);
        kin_->assemble(traction_, scratch_, &K);
    }

    ContactResultant resultant() const override {
        ContactResultant r;
        if (traction_.size() != kin_->n_points()) {
            return r; // before the first pairing: nothing in contact yet
        }
        for (std::size_t i = 0; i < kin_->n_points(); ++i) {
            const ContactKinematics& k = kin_->point(i);
            if (!k.active) {
                continue;
            }
            const ContactTraction& t = traction_[i];
            const double w = k.weight;
            r.area += w;
            ++r.active;
            r.closed += t.t_N < 0.0 ? 1 : 0;
            r.t_N += w * t.t_N;
            for (std::size_t d = 0; d < 3; ++d) {
                r.shear[d] += w * (t.tau[0] * k.t1[d] + t.tau[1] * k.t2[d]);
            }
            add_state_means(i, w, r);
        }
        if (r.area > 0.0) {
            r.t_N /= r.area;
            for (double& v : r.shear) {
                v /= r.area;
            }
            r.void_ratio /= r.area;
            r.eps_N /= r.area;
            r.band_thickness /= r.area;
            r.sigma_p1 /= r.area;
            r.sigma_p2 /= r.area;
        }
        return r;
    }

protected:
    virtual bool needs_stress() const = 0; // s_p1, s_p2 every increment
    virtual void refresh_jacobian() {}     // Jacobian columns of the last evaluate() if deferred
    virtual void start(const std::vector<Voigt6>& local_stress) = 0;
    virtual void add_state_means(std::size_t, double, ContactResultant&) const {}
    virtual void new_increment() {}

    // Continuum stress at each slave point (Eq. 14) rotated into its engine frame (Eq. 15).
    void extrapolate(const ElementStresses& stresses) {
        std::vector<Voigt6> at_points;
        for (std::size_t i = 0; i < kin_->n_points(); ++i) {
            const ContactKinematics& k = kin_->point(i);
            stresses(k.slave_element, at_points);
            const Voigt6 s = extrapolate_stress(dim_, at_points, k.slave_natural.data());
            const PointFrame& f = frames_[i];
            local_stress_[i] = rotate_to_frame(s, f.n, f.t1, f.t2);
        }
    }

    // Normal traction of the penalty and its derivative for point i's current gap.
    std::array<double, 2> penalty(std::size_t i) const {
        const ContactKinematics& k = kin_->point(i);
        const double g = k.g_N - gap_offset_[i];
        if (!k.active || g > 0.0) {
            return {0.0, 0.0};
        }
        return {spec_.normal_penalty * g, spec_.normal_penalty};
    }

    // Gaps for the trial increment into the engine's input columns (the column indices of
    // its point layout: t_N, k_N, dg1, dg2), the frame of every point.
    template <class Points>
    void gather_gaps(const std::vector<double>& du, Points& cp, int col_t_N, int col_k_N,
                     int col_dg1, int col_dg2) {
        kin_->update_gaps(du);
        scratch_.resize(du.size());
        for (std::size_t i = 0; i < kin_->n_points(); ++i) {
            const PointFrame& f = frames_[i];
            cp.set_frame(i, f.n.data(), f.t1.data(), f.t2.data());
            const auto [t_N, k_N] = penalty(i);
            const auto dg = f.to_local(kin_->point(i).dg_T);
            const bool active = kin_->point(i).active;
            cp.input(col_t_N)[i] = t_N;
            cp.input(col_k_N)[i] = k_N;
            cp.input(col_dg1)[i] = active ? dg[0] : 0.0;
            cp.input(col_dg2)[i] = active ? dg[1] : 0.0;
        }
    }

    // Engine outputs (local traction, Jacobian columns) of point i into the kinematic frame.
    template <class Points>
    void take_traction(const Points& cp, std::size_t i) {
        const PointFrame& f = frames_[i];
        ContactTraction& t = traction_[i];
        if (!kin_->point(i).active) {
            t = {};
            return;
        }
        t.t_N = cp.output(contact_col::traction)[i];
        t.tau = f.to_kinematic(cp.output(contact_col::traction + 1)[i],
                               cp.output(contact_col::traction + 2)[i]);
        for (int c = 0; c < 2 * dim_; ++c) {
            const auto cu = static_cast<std::size_t>(c);
            t.jac[0][cu] = cp.jacobian(i, 0, c);
            const auto tau = f.to_kinematic(cp.jacobian(i, 1, c), cp.jacobian(i, 2, c));
            t.jac[1][cu] = tau[0];
            t.jac[2][cu] = tau[1];
        }
    }

    ContactPairSpec spec_;
    std::unique_ptr<MortarKinematics> kin_;
    int dim_;
    bool first_ = true;
    std::vector<PointFrame> frames_;
    std::vector<Voigt6> local_stress_;
    std::vector<double> gap_offset_;
    std::vector<ContactTraction> traction_;
    std::vector<double> scratch_; // forces of add_tangent's assembly, discarded
};

class CoulombPair final : public PairBase {
public:
    CoulombPair(const Mesh& mesh, ContactPairSpec spec)
        : PairBase(mesh, std::move(spec)), points_(slave_point_count(mesh, spec_), dim_) {
        if (spec_.friction.friction_coefficient < 0.0 ||
            !(spec_.friction.tangential_stiffness > 0.0)) {
            throw std::invalid_argument(fmt::format(
                "contact pair '{}': expected a friction coefficient >= 0 and a positive "
                "tangential stiffness",
                spec_.name));
        }
    }

    bool evaluate(const std::vector<double>& du, std::vector<double>& f_int,
                  std::string&) override {
        {
            PhaseTimer timer(timers_.gather);
            gather_gaps(du, points_, coulomb_col::t_N, coulomb_col::k_N, coulomb_col::dg1,
                        coulomb_col::dg2);
        }
        CoulombContactReport rep;
        {
            PhaseTimer timer(timers_.kernels);
            rep = coulomb_contact_update(points_, spec_.friction, {});
        }
        PhaseTimer timer(timers_.scatter);
        ++counters_.evaluations;
        counters_.point_updates += static_cast<double>(rep.points);
        counters_.lanes += rep.evaluations;
        counters_.constitutive_evaluations += rep.evaluations;
        for (std::size_t i = 0; i < kin_->n_points(); ++i) {
            take_traction(points_, i);
        }
        kin_->assemble(traction_, f_int, nullptr);
        return true;
    }

    void commit() override { points_.commit(); }

protected:
    bool needs_stress() const override { return false; }
    void start(const std::vector<Voigt6>&) override {
        for (std::size_t i = 0; i < points_.size(); ++i) {
            points_.set_traction(i, 0.0, 0.0);
        }
    }

private:
    CoulombContactPoints points_;
};

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
        }
        // Deferred Jacobian: the residual needs only the base lanes; the Eq. 37 lanes run when
        // the solver asks for the tangent (not after the residual that converges).
        defer_ = spec_.defer_jacobian && spec_.options.jacobian != ContactJacobian::analytical;
        ContactReport rep;
        {
            PhaseTimer timer(timers_.kernels);
            rep = engine_.update(points_, params_, defer_ ? base_only_ : spec_.options);
        }
        while (!rep.ok() && relax_failed_points()) {
            PhaseTimer timer(timers_.kernels);
            count(rep);
            ++counters_.relaxed_reruns;
            rep = engine_.update(points_, params_, defer_ ? base_only_ : spec_.options);
        }
        PhaseTimer timer(timers_.scatter);
        count(rep);
        if (!rep.ok()) {
            ++counters_.failed_evaluations;
            const std::size_t i = rep.first_failed;
            const ContactKinematics& k = kin_->point(i);
            error = fmt::format(
                "{} interface point(s) of contact pair '{}' failed in Algorithm 1, first point "
                "{} at ({:.6g}, {:.6g}, {:.6g}): {} (residual {:.3e}); {}",
                rep.failed, spec_.name, i, k.x[0], k.x[1], k.x[2],
                interface_failure::describe(rep.first_failed_cause), rep.first_failed_residual,
                describe_point(i));
            return false;
        }
        for (std::size_t i = 0; i < kin_->n_points(); ++i) {
            take_traction(points_, i);
        }
        kin_->assemble(traction_, f_int, nullptr);
        return true;
    }

    void commit() override {
        points_.commit();
        for (double l : relax_) {
            counters_.relaxed_point_updates += l < 1.0 ? 1.0 : 0.0;
        }
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
    void set_targets(std::size_t i) {
        const double l = relax_.empty() ? 1.0 : relax_[i];
        const double t_N = points_.input(contact_col::t_N)[i];
        for (int c = 1; c <= 2; ++c) {
            double s_p = local_stress_[i][static_cast<std::size_t>(c)];
            if (t_N < 0.0) {
                s_p = std::clamp(s_p, t_N / k_lo_, k_lo_ * t_N);
            }
            points_.input(contact_col::s_p1 + c - 1)[i] = l >= 1.0 ? s_p : t_N + l * (s_p - t_N);
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
            if (points_.output(contact_col::status)[i] > -0.5 || relax_[i] <= 0.0) {
                continue;
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
        const std::vector<Voigt6> before = local_stress_;
        extrapolate(stresses);
        double change = 0.0;
        for (std::size_t i = 0; i < before.size(); ++i) {
            if (!kin_->point(i).active) {
                continue;
            }
            for (std::size_t c = 1; c <= 2; ++c) {
                const double ref = std::max({std::abs(before[i][c]), 1.0});
                change = std::max(change, std::abs(local_stress_[i][c] - before[i][c]) / ref);
            }
        }
        return change;
    }

    void new_increment() override {
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
        }
    }

    void count(const ContactReport& rep) {
        ++counters_.evaluations;
        counters_.point_updates += static_cast<double>(rep.points);
        counters_.lanes += rep.lanes;
        counters_.subincrements += rep.subincrements;
        counters_.constitutive_evaluations += rep.constitutive_evaluations;
        counters_.interface_newton_iterations += rep.newton_iterations;
        counters_.band_clamped += static_cast<long>(rep.band_clamped);
        counters_.dropped_columns += rep.dropped_columns;
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

private:
    typename M::Params params_;
    ContactOptions base_only_;  // the spec's options without the Eq. 37 lanes
    bool defer_ = false;        // the last evaluate() ran the base lanes only
    std::vector<double> relax_; // per point: share lambda of the continuum's in-plane targets
    std::vector<int> calm_;     // per point: increments since its last relaxation
    double k_lo_ = 0.5;         // 1 - sin(kappa phi_c): at-rest bounds of the in-plane targets
    ContactPoints<M> points_;
    ContactEngine<M> engine_;
};

} // namespace

std::unique_ptr<ContactPair> make_contact_pair(const Mesh& mesh, ContactPairSpec spec) {
    mesh.face_set(spec.slave_faces); // throws naming the set
    mesh.face_set(spec.master_faces);
    if (spec.coulomb) {
        return std::make_unique<CoulombPair>(mesh, std::move(spec));
    }
    return std::visit(
        [&](const auto& p) -> std::unique_ptr<ContactPair> {
            using P = std::decay_t<decltype(p)>;
            using M = typename model_of<P>::type;
            if constexpr (std::is_same_v<M, LinearElastic>) {
                throw std::invalid_argument(fmt::format(
                    "contact pair '{}': linear-elastic cannot be an interface model (it has no "
                    "void ratio); expected hypoplasticity or sanisand",
                    spec.name));
            } else {
                return std::make_unique<InterfacePair<M>>(mesh, spec, p);
            }
        },
        spec.interface_material);
}

} // namespace ifsim::fem
