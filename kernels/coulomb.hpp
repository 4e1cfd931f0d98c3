#pragma once
// Coulomb friction with penalty regularisation of the stick state, the cheap interface model
// for smooth surfaces (paper §6.1: mu = tan(delta), tangential stiffness k_t).
//
// Exact return mapping for one increment of the tangential gap dg (local t1, t2):
//   trial  tau_tr = tau_n + k_t dg
//   stick  |tau_tr| <= mu |t_N|  ->  tau = tau_tr
//   slip   tau = mu |t_N| tau_tr / |tau_tr|          (radial return onto the friction cone)
//   open   t_N >= 0 (no contact pressure)  ->  tau = 0
// Because the slip surface is a circle in the (tau1, tau2) plane and the stiffness is isotropic,
// the radial return is the exact solution of the incremental problem, not an approximation.

#include "kernels/simd.hpp"

namespace ifsim {

struct CoulombParams {
    double friction_coefficient = 0.25;  // mu
    double tangential_stiffness = 6.0e3; // k_t, kPa/m
};

template <class T>
struct CoulombResult {
    T tau1, tau2;             // new tangential traction (kPa)
    simd::mask_t<T> slipping; // on the friction cone
    simd::mask_t<T> open;     // no contact pressure
    // Consistent derivatives: d tau_a / d dg_b and d tau_a / d t_N.
    T dtau_ddg[2][2];
    T dtau_dtN[2];
};

template <class T>
CoulombResult<T> coulomb_update(const CoulombParams& p, const T& t_N, const T& tau1_old,
                                const T& tau2_old, const T& dg1, const T& dg2) {
    CoulombResult<T> r;
    const double k = p.tangential_stiffness;
    const T tr1 = tau1_old + k * dg1;
    const T tr2 = tau2_old + k * dg2;
    const T tr_norm = simd::sqrt(tr1 * tr1 + tr2 * tr2);
    const T limit = p.friction_coefficient * simd::max(-t_N, T(0.0));
    r.open = t_N >= 0.0;
    r.slipping = (tr_norm > limit) && !r.open;
    const T safe = simd::max(tr_norm, T(1.0e-300));
    const T n1 = tr1 / safe;
    const T n2 = tr2 / safe;
    const T scale = simd::select(r.slipping, limit / safe, T(1.0));
    r.tau1 = simd::select(r.open, T(0.0), tr1 * scale);
    r.tau2 = simd::select(r.open, T(0.0), tr2 * scale);
    // Stick: k I. Slip: k mu|t_N|/|tau_tr| (I - n n). Open: 0.
    const T ks = simd::select(r.open, T(0.0), k * scale);
    const T kn = simd::select(r.slipping, ks, T(0.0));
    r.dtau_ddg[0][0] = ks - kn * n1 * n1;
    r.dtau_ddg[0][1] = -kn * n1 * n2;
    r.dtau_ddg[1][0] = -kn * n2 * n1;
    r.dtau_ddg[1][1] = ks - kn * n2 * n2;
    // d(mu |t_N|)/d t_N = -mu while in compression.
    const T dl = simd::select(r.slipping, T(-p.friction_coefficient), T(0.0));
    r.dtau_dtN[0] = dl * n1;
    r.dtau_dtN[1] = dl * n2;
    return r;
}

} // namespace ifsim
