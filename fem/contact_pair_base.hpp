#pragma once
// What every contact pair shares (fem/contact_pair.cpp, fem/interface_pair.hpp): the mortar
// kinematics of the mesh's dimension, the engine frame of each point (the kinematic frame
// turned towards the preferred shear direction), the penalty with its offsets, and the
// tractions of the last evaluation. Internal to the contact pairs.

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "fem/contact_pair.hpp"
#include "fem/mortar_kinematics.hpp"
#include "fem/phase_timer.hpp"

namespace ifsim::fem::detail {

using Vec3 = std::array<double, 3>;

inline double dot(const Vec3& a, const Vec3& b) {
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
inline double interface_friction_sine(const HypoplasticityParams& p) {
    return std::sin(p.roughness * p.phi_c);
}
inline double interface_friction_sine(const SanisandParams& p) {
    const double phi_c = std::asin(3.0 * p.M_c / (6.0 + p.M_c)); // M_c = 6 sin / (3 - sin)
    return std::sin(p.roughness * phi_c);
}

// Slave integration points: 2-point Gauss per edge (2D), 2x2 per face (3D).
inline std::size_t slave_point_count(const Mesh& mesh, const ContactPairSpec& spec) {
    return (mesh.dim() == 2 ? 2 : 4) * mesh.face_set(spec.slave_faces).size();
}

inline std::unique_ptr<MortarKinematics> make_kinematics(const Mesh& mesh,
                                                         const ContactPairSpec& spec) {
    return make_mortar_contact(mesh, spec.slave_faces, spec.master_faces);
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
    void set_increment_length(double dt) override { increment_length_ = dt; }
    void set_viscous_retry(bool on) override { viscous_retry_ = on; }

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
        viscous_.assign(n, {0.0, 0.0});
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

    std::vector<ContactPointRecord> point_records() const override {
        std::vector<ContactPointRecord> out(kin_->n_points());
        const bool evaluated = traction_.size() == kin_->n_points();
        for (std::size_t i = 0; i < out.size(); ++i) {
            const ContactKinematics& k = kin_->point(i);
            ContactPointRecord& r = out[i];
            r.slave_element = k.slave_element;
            r.natural = k.slave_natural;
            r.active = k.active;
            r.weight = k.weight;
            if (evaluated && k.active) {
                const ContactTraction& t = traction_[i];
                r.t_N = t.t_N;
                for (std::size_t d = 0; d < 3; ++d) {
                    r.shear[d] = t.tau[0] * k.t1[d] + t.tau[1] * k.t2[d];
                }
            }
            r.open = (!k.active || r.t_N >= 0.0) ? 1.0 : 0.0;
            if (evaluated) {
                add_point_state(i, r);
            }
        }
        return out;
    }

    ContactPairSnapshot snapshot() const override {
        ContactPairSnapshot s;
        s.started = !first_;
        s.gap_offset = gap_offset_;
        save_state(s);
        return s;
    }
    void restore(const ContactPairSnapshot& s) override {
        first_ = !s.started;
        gap_offset_ = s.gap_offset;
        load_state(s);
    }

protected:
    // The points' committed state (and a pair's own) into and out of a snapshot.
    virtual void save_state(ContactPairSnapshot& s) const = 0;
    virtual void load_state(const ContactPairSnapshot& s) = 0;

    // Column after column, the first n points of each: points.committed(c)[i].
    template <class Points>
    static void save_columns(const Points& points, int columns, ContactPairSnapshot& s) {
        for (int c = 0; c < columns; ++c) {
            const double* col = points.committed(c);
            s.committed.insert(s.committed.end(), col, col + points.size());
        }
    }
    template <class Points>
    void load_columns(Points& points, int columns, const ContactPairSnapshot& s) const {
        if (s.committed.size() != static_cast<std::size_t>(columns) * points.size()) {
            throw std::invalid_argument(
                fmt::format("contact pair '{}': a snapshot of {} state values for {} points "
                            "of {} columns",
                            spec_.name, s.committed.size(), points.size(), columns));
        }
        for (int c = 0; c < columns; ++c) {
            std::copy_n(s.committed.begin() + static_cast<long>(c * points.size()), points.size(),
                        points.committed(c));
        }
    }

    virtual bool needs_stress() const = 0; // s_p1, s_p2 every increment
    virtual void refresh_jacobian() {}     // Jacobian columns of the last evaluate() if deferred
    virtual void start(const std::vector<Voigt6>& local_stress) = 0;
    virtual void add_state_means(std::size_t, double, ContactResultant&) const {}
    virtual void add_point_state(std::size_t, ContactPointRecord&) const {}
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

    // Slip viscosity: tau_v = eta dg_T / dt added to point i's traction (kinematic axes) and
    // its tangent, d dg_T,a / d u = -t_a (slave) and +t_a (master) (Eq. A13). Only where the
    // point presses (t_N < 0): a separated point carries nothing. tau is conjugate to dg_T
    // (fem/mortar_kinematics.hpp), so the viscous work tau_v . dg_T >= 0 is dissipated.
    void add_slip_viscosity(std::size_t i) {
        viscous_[i] = {0.0, 0.0};
        const ContactKinematics& k = kin_->point(i);
        ContactTraction& t = traction_[i];
        const bool on = spec_.slip_viscosity_always || viscous_retry_;
        if (spec_.slip_viscosity <= 0.0 || !on || !k.active || !(t.t_N < 0.0)) {
            return;
        }
        const double c = spec_.slip_viscosity / increment_length_;
        for (std::size_t a = 0; a < 2; ++a) {
            const std::array<double, 3>& ta = a == 0 ? k.t1 : k.t2;
            viscous_[i][a] = c * k.dg_T[a];
            t.tau[a] += viscous_[i][a];
            for (int d = 0; d < dim_; ++d) {
                const auto du = static_cast<std::size_t>(d);
                t.jac[1 + a][du] -= c * ta[du];
                t.jac[1 + a][static_cast<std::size_t>(dim_ + d)] += c * ta[du];
            }
        }
    }

    // At commit: how much of the committed shear the viscosity carried.
    void count_slip_viscosity(ContactPairCounters& counters) const {
        if (spec_.slip_viscosity <= 0.0) {
            return;
        }
        for (std::size_t i = 0; i < viscous_.size() && i < traction_.size(); ++i) {
            const ContactTraction& t = traction_[i];
            const double v = std::hypot(viscous_[i][0], viscous_[i][1]);
            if (v == 0.0) {
                continue;
            }
            const double band = std::hypot(t.tau[0] - viscous_[i][0], t.tau[1] - viscous_[i][1]);
            const double share = v / std::max(band, 0.01 * std::abs(t.t_N));
            counters.viscous_traction_max = std::max(counters.viscous_traction_max, v);
            counters.viscous_share_max = std::max(counters.viscous_share_max, share);
            counters.viscous_point_updates += share > 0.01 ? 1.0 : 0.0;
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
    std::vector<std::array<double, 2>> viscous_; // slip viscosity's share of traction_ (tau)
    double increment_length_ = 1.0;              // the increment's share of its nominal step
    bool viscous_retry_ = false;                 // the solver retries a failed increment
    std::vector<double> scratch_;                // forces of add_tangent's assembly, discarded
};

} // namespace ifsim::fem::detail
