#pragma once
// Hypoplasticity of von Wolffersdorff (1996) with the intergranular strain extension of
// Niemunis & Herle (1997) and the interface roughness modification of Staubach, Machacek &
// Wichtmann (2022), Eqs. 30-32. Equations and choices: docs/models.md.
//
// State (flat, see model_api.hpp): [0..5] T, [6] e, [7..12] h (intergranular strain, tensor
// shear components), [13] the substep strain carried to the next update (0 = none yet; see
// kernels/explicit_integration.hpp). Mechanical sign convention throughout (compression negative).

#include <array>
#include <cmath>
#include <limits>

#include "kernels/explicit_integration.hpp"
#include "kernels/model_api.hpp"

namespace ifsim {

struct HypoplasticityParams {
    double phi_c = 0.0; // critical friction angle (rad)
    double h_s = 0.0;   // granular hardness (kPa)
    double n = 0.0;
    double e_i0 = 0.0, e_c0 = 0.0, e_d0 = 0.0;
    double alpha = 0.0, beta = 0.0;
    // intergranular strain
    double m_R = 1.0, m_T = 1.0, R = 1.0e-4, beta_R = 0.5, chi = 1.0;
    bool intergranular_strain = true;
    double roughness = 1.0; // kappa <= 1 (Eq. 28); 1 = continuum behaviour

    // Derived constants, filled by prepare().
    double a = 0.0;        // Eq. 30 with kappa*phi_c
    double alpha_k = 0.0;  // alpha*kappa^2 (Eq. 31)
    double fb_const = 0.0; // h_s/n (e_i0/e_c0)^beta / [3 + a^2 - a sqrt3 (...)^alpha_k] (Eq. 32)

    void prepare() {
        const double s = std::sin(roughness * phi_c);
        a = std::sqrt(3.0) * (3.0 - s) / (2.0 * std::sqrt(2.0) * s);
        alpha_k = alpha * roughness * roughness;
        const double bracket =
            3.0 + a * a - a * std::sqrt(3.0) * std::pow((e_i0 - e_d0) / (e_c0 - e_d0), alpha_k);
        fb_const = h_s / n * std::pow(e_i0 / e_c0, beta) / bracket;
    }
};

struct Hypoplasticity {
    static constexpr const char* name = "hypoplasticity";
    static constexpr int n_state = 14;
    static constexpr int h_index = 7;
    static constexpr int substep_index = 13;
    // Integrated by integrate_explicit, attempt by attempt: the engine refills finished SIMD
    // lanes.
    static constexpr bool lane_refill = true;

    // The Matsuoka-Nakai value I1 I2 / I3 of a compressive stress and its value on the model's
    // limit surface, that of kappa*phi_c (von Wolffersdorff's critical states lie on it). A
    // stress above the limit lies outside the surface: no hypoplastic path holds it, e.g. a
    // band of kappa = 0.05 (1.7 degrees) asked to carry sigma_p = sigma_N / 2.
    struct LimitSurface {
        double value = 0.0, limit = 0.0;
        bool outside() const { return value > limit; }
    };
    static LimitSurface matsuoka_nakai(const HypoplasticityParams& p, const Sym<double>& s) {
        const double I1 = s[0] + s[1] + s[2];
        const double I2 =
            s[0] * s[1] + s[1] * s[2] + s[2] * s[0] - s[3] * s[3] - s[4] * s[4] - s[5] * s[5];
        const double I3 = s[0] * (s[1] * s[2] - s[5] * s[5]) - s[3] * (s[3] * s[2] - s[5] * s[4]) +
                          s[4] * (s[3] * s[5] - s[1] * s[4]);
        const double sin2 = std::pow(std::sin(p.roughness * p.phi_c), 2);
        return {I3 < 0.0 ? I1 * I2 / I3 : std::numeric_limits<double>::infinity(),
                (9.0 - sin2) / (1.0 - sin2)};
    }
    static constexpr bool pressure_floor = true;
    using Params = HypoplasticityParams;
    template <class T>
    using State = StateVec<T, n_state>;

    // Pressure-dependent quantities of the hypoplastic core at stress T (Bauer law etc.).
    template <class T>
    struct Core {
        Sym<T> That;     // T / tr T
        Sym<T> That_dev; // deviator of That
        T factor;        // f_b f_e / (That : That)
        T F;             // Matsuoka-Nakai shape function
        T f_d;           // pyknotropy factor
    };

    template <class T>
    static Core<T> core(const Params& p, const Sym<T>& stress, const T& e_in, double p_min) {
        Core<T> c;
        const T trT = simd::min(voigt::trace(stress), T(-3.0 * p_min));
        const T inv_tr = 1.0 / trT;
        c.That = voigt::scale(stress, inv_tr);
        c.That_dev = voigt::deviator(c.That);
        const T TT = voigt::ddot(c.That, c.That);
        const T dev2 = voigt::ddot(c.That_dev, c.That_dev);
        const T dev_norm = simd::sqrt(dev2);
        const T tan_psi = std::sqrt(3.0) * dev_norm;
        const T safe_dev = simd::max(dev2, T(1.0e-30));
        T cos3t =
            -std::sqrt(6.0) * voigt::trace_cube(c.That_dev) / (safe_dev * simd::sqrt(safe_dev));
        cos3t = simd::select(dev_norm > 1.0e-12, cos3t, T(1.0));
        cos3t = simd::max(T(-1.0), simd::min(T(1.0), cos3t));
        const T denom = simd::max(2.0 + std::sqrt(2.0) * tan_psi * cos3t, T(1.0e-10));
        const T arg = tan_psi * tan_psi * 0.125 + (2.0 - tan_psi * tan_psi) / denom;
        c.F = simd::sqrt(simd::max(arg, T(0.0))) - tan_psi / (2.0 * std::sqrt(2.0));

        // Bauer compression law for the limit void ratios (3p = -tr T).
        // Powers as exp(y log x), sharing the logarithms (fewer transcendental calls per rate).
        const T ratio = -trT / p.h_s;
        const T ratio_n = simd::exp(p.n * simd::log(ratio));
        const T bauer = simd::exp(-ratio_n);
        const T e_i = p.e_i0 * bauer;
        const T e_c = p.e_c0 * bauer;
        const T e_d = p.e_d0 * bauer;
        const T e = simd::max(e_in, T(1.0e-6));
        // Outside [e_d, e_i] the model is outside its admissible range; f_d = 0 below e_d.
        const T fd_base = simd::max(e - e_d, T(0.0)) / (e_c - e_d);
        c.f_d = simd::select(fd_base > 0.0, simd::exp(p.alpha_k * simd::log(fd_base)), T(0.0));
        const T f_e = simd::exp(p.beta * simd::log(e_c / e));
        const T f_b = p.fb_const * (1.0 + e_i) / e_i * (ratio / ratio_n); // (3p/h_s)^(1-n)
        c.factor = f_b * f_e / TT;
        return c;
    }

    // L : X of the hypoplastic core.
    template <class T>
    static Sym<T> apply_L(const Params& p, const Core<T>& c, const Sym<T>& X) {
        const T F2 = c.F * c.F;
        const T tx = voigt::ddot(c.That, X) * (p.a * p.a);
        Sym<T> r;
        for (int i = 0; i < 6; ++i) {
            r[i] = c.factor * (F2 * X[i] + tx * c.That[i]);
        }
        return r;
    }
    // N (without the norm of D).
    template <class T>
    static Sym<T> N_tensor(const Params& p, const Core<T>& c) {
        const T s = c.factor * c.f_d * p.a * c.F;
        Sym<T> r;
        for (int i = 0; i < 6; ++i) {
            r[i] = s * (c.That[i] + c.That_dev[i]);
        }
        return r;
    }

    // Intergranular strain quantities for direction D.
    template <class T>
    struct Igs {
        Sym<T> h_dir;            // h / |h| (zero for h = 0)
        T rho;                   // |h| / R, clamped to 1
        T log_rho;               // log(rho), shared by rho^chi and rho^beta_R
        T rho_chi;               // rho^chi
        simd::mask_t<T> loading; // h_dir : D > 0
    };
    template <class T>
    static Igs<T> igs(const Params& p, const Sym<T>& h, const Sym<T>& D) {
        Igs<T> g;
        const T hn = voigt::norm(h);
        const simd::mask_t<T> nonzero = hn > 1.0e-14 * p.R;
        const T inv = simd::select(nonzero, 1.0 / simd::max(hn, T(1.0e-300)), T(0.0));
        g.h_dir = voigt::scale(h, inv);
        g.rho = simd::min(hn / p.R, T(1.0));
        g.log_rho = simd::log(simd::max(g.rho, T(1.0e-300)));
        g.rho_chi = simd::select(g.rho > 0.0, simd::exp(p.chi * g.log_rho), T(0.0));
        g.loading = voigt::ddot(g.h_dir, D) > 0.0;
        return g;
    }

    // M(y, direction of D) : X, the stiffness of the intergranular strain model for the
    // loading branch selected by D (Niemunis & Herle 1997). With X = D this is the stress rate.
    template <class T>
    static Sym<T> stiffness_apply(const Params& p, const Core<T>& c, const Igs<T>& g,
                                  const Sym<T>& D, const Sym<T>& X) {
        const Sym<T> LX = apply_L(p, c, X);
        const Sym<T> N = N_tensor(p, c);
        if (!p.intergranular_strain) {
            // L : X + N (D/|D|) : X
            const T dn = voigt::norm(D);
            const T proj =
                simd::select(dn > 0.0, voigt::ddot(D, X) / simd::max(dn, T(1.0e-300)), T(0.0));
            return voigt::axpy(LX, proj, N);
        }
        const Sym<T> Lh = apply_L(p, c, g.h_dir);
        const T hX = voigt::ddot(g.h_dir, X);
        const T mfac = g.rho_chi * p.m_T + (1.0 - g.rho_chi) * p.m_R;
        const T c_load = g.rho_chi * (1.0 - p.m_T);
        const T c_unload = g.rho_chi * (p.m_R - p.m_T);
        const T cLh = simd::select(g.loading, c_load, c_unload) * hX;
        const T cN = simd::select(g.loading, g.rho_chi * hX, T(0.0));
        Sym<T> r;
        for (int i = 0; i < 6; ++i) {
            r[i] = mfac * LX[i] + cLh * Lh[i] + cN * N[i];
        }
        return r;
    }

    // flatten: keeps xsimd's exp and log inlined in the hot rate (the compiler stopped doing so
    // once h's rate was shared with h's own integration: 10-15 % of the contact engine's time).
    template <class T>
    [[gnu::flatten]] static State<T> euler_increment(const Params& p, const IntegrationSettings& s,
                                                     const State<T>& y, const Sym<T>& de) {
        const Sym<T> stress = stress_of(y);
        const T e = y[state_index::void_ratio];
        const Core<T> c = core(p, stress, e, s.min_pressure);
        const Sym<T> h = sym_at(y, h_index);
        const Igs<T> g = igs(p, h, de);
        const Sym<T> ds = stiffness_apply(p, c, g, de, de);
        State<T> dy;
        set_stress(dy, ds);
        dy[state_index::void_ratio] = (1.0 + e) * voigt::trace(de);
        set_sym_at(dy, h_index, p.intergranular_strain ? h_increment(p, g, de) : voigt::zero<T>());
        dy[substep_index] = T(0.0);
        return dy;
    }

    // Evolution of h (Niemunis & Herle 1997): dh = (I - rho^beta_R h_dir (x) h_dir) : de when
    // loading (h_dir : de > 0), dh = de otherwise.
    template <class T>
    static Sym<T> h_increment(const Params& p, const Igs<T>& g, const Sym<T>& de) {
        const T rho_b = simd::select(g.rho > 0.0, simd::exp(p.beta_R * g.log_rho), T(0.0));
        const T proj = simd::select(g.loading, rho_b * voigt::ddot(g.h_dir, de), T(0.0));
        return voigt::axpy(de, -proj, g.h_dir);
    }

    // h evolves with itself and the strain only, not with stress or void ratio: the integrator
    // may integrate it on its own (kernels/explicit_integration.hpp, split_internal).
    static constexpr int internal_index = h_index;
    static bool has_internal(const Params& p) { return p.intergranular_strain; }
    static double internal_scale(const Params& p) { return p.R; }
    template <class T>
    static Sym<T> internal_increment(const Params& p, const Sym<T>& h, const Sym<T>& de) {
        // igs() without rho^chi, which h's own rate does not need
        Igs<T> g;
        const T hn = voigt::norm(h);
        const T inv = simd::select(hn > 1.0e-14 * p.R, 1.0 / simd::max(hn, T(1.0e-300)), T(0.0));
        g.h_dir = voigt::scale(h, inv);
        g.rho = simd::min(hn / p.R, T(1.0));
        g.log_rho = simd::log(simd::max(g.rho, T(1.0e-300)));
        g.loading = voigt::ddot(g.h_dir, de) > 0.0;
        return h_increment(p, g, de);
    }
    // Fraction of the strain de after which h : de turns positive (unloading switches to
    // loading: the rate has a kink there); above 1 when it does not within de. Before it h
    // moves linearly (dh = de).
    template <class T>
    static T internal_switch(const Params&, const Sym<T>& h, const Sym<T>& de) {
        const T hd = voigt::ddot(h, de);
        const T dd = voigt::ddot(de, de);
        return simd::select((hd < 0.0) && (dd > 0.0), -hd / simd::max(dd, T(1.0e-300)), T(2.0));
    }
    template <class T>
    static void correct_internal(const Params& p, Sym<T>& h) {
        const T hn = voigt::norm(h);
        const T s = simd::select(hn > p.R, p.R / simd::max(hn, T(1.0e-300)), T(1.0));
        h = voigt::scale(h, s);
    }

    template <class T>
    static T local_error(const Params& p, const IntegrationSettings& s, const State<T>& yE,
                         const State<T>& yH) {
        const Sym<T> sH = stress_of(yH);
        const T sn = simd::max(voigt::norm(sH), T(1.0e-3));
        const T err_s = voigt::norm(voigt::sub(sH, stress_of(yE))) / sn;
        const T err_e = simd::abs(yH[6] - yE[6]) / simd::max(simd::abs(yH[6]), T(1.0e-3));
        T err = simd::max(err_s, err_e);
        if (p.intergranular_strain && s.state_error_weight > 0.0) {
            const T err_h = voigt::norm(voigt::sub(sym_at(yH, h_index), sym_at(yE, h_index))) *
                            (s.state_error_weight / p.R);
            err = simd::max(err, err_h);
        }
        return err;
    }

    template <class T>
    static simd::mask_t<T> admissible(const Params& /*p*/, const IntegrationSettings& s,
                                      const State<T>& y) {
        return state_finite<T, n_state>(y) && (mean_pressure(stress_of(y)) >= s.min_pressure) &&
               (y[state_index::void_ratio] > 0.0);
    }

    template <class T>
    static void correct(const Params& p, State<T>& y) {
        if (!p.intergranular_strain) {
            return;
        }
        Sym<T> h = sym_at(y, h_index);
        correct_internal(p, h);
        set_sym_at(y, h_index, h);
    }

    // Tension cut-off: isotropic stress at the pressure floor; e and h follow the strain.
    template <class T>
    static State<T> cut_off(const Params& p, const IntegrationSettings& s, const State<T>& y,
                            const Sym<T>& de_rest) {
        State<T> r = y;
        set_stress(r, voigt::scale(voigt::identity<T>(), T(-s.min_pressure)));
        r[6] = simd::max(y[6] + (1.0 + y[6]) * voigt::trace(de_rest), T(1.0e-6));
        if (p.intergranular_strain) {
            set_sym_at(r, h_index, voigt::add(sym_at(y, h_index), de_rest));
            correct(p, r);
        }
        return r;
    }

    template <class T>
    static void integrate(const Params& p, const IntegrationSettings& s,
                          const SubstepControl<T>& control, State<T>& y, const Sym<T>& deps,
                          UpdateStats<T>& stats) {
        integrate_explicit<Hypoplasticity, T>(p, s, control, y, deps, stats);
    }

    // The cheap rate stiffness: M(y, direction of deps) of the intergranular strain model (or
    // L + N (x) D/|D| without it) at the start state, as 6 columns dsigma/deps_j (tensor
    // components; the shear column j perturbs eps_ij and eps_ji together).
    template <class T>
    static std::array<Sym<T>, 6> rate_stiffness(const Params& p, const IntegrationSettings& s,
                                                const State<T>& y, const Sym<T>& deps) {
        const Core<T> c = core(p, stress_of(y), y[state_index::void_ratio], s.min_pressure);
        const Igs<T> g = igs(p, sym_at(y, h_index), deps);
        std::array<Sym<T>, 6> cols;
        for (int j = 0; j < 6; ++j) {
            Sym<T> unit = voigt::zero<T>();
            unit[j] = T(1.0);
            cols[j] = stiffness_apply(p, c, g, deps, unit);
        }
        return cols;
    }
};

} // namespace ifsim
