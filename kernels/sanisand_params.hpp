#pragma once
// Parameters of Sanisand 2004 (Dafalias & Manzari 2004, J Eng Mech 130(6)) with the interface
// roughness factor kappa of Staubach, Machacek & Wichtmann (2022), Eqs. 33-35.
// Equations and choices: docs/models.md (Sanisand).

#include <cmath>

namespace ifsim {

struct SanisandParams {
    double p_a = 100.0; // reference pressure (kPa)
    double e0 = 0.0;    // intercept of the critical state line e_c = e0 - lambda_c (p/p_a)^xi
    double lambda_c = 0.0;
    double xi = 0.0;
    double M_c = 0.0; // critical stress ratio in triaxial compression
    double c = 0.0;   // M_e / M_c
    double m = 0.0;   // opening of the yield cone
    double G0 = 0.0;  // shear modulus constant (dimensionless)
    double nu = 0.0;
    double h0 = 0.0, c_h = 0.0, n_b = 0.0; // kinematic hardening
    double A0 = 0.0, n_d = 0.0;            // dilatancy
    double z_max = 0.0, c_z = 0.0;         // fabric
    double roughness = 1.0;                // kappa <= 1 (paper Eq. 28); 1 = continuum behaviour

    // Derived, filled by prepare().
    double M_c_eff = 0.0;  // Eq. 33 for kappa < 1, else M_c
    double c_eff = 0.0;    // |M_e|/M_c of Eq. 33 for kappa < 1, else c
    double n_b_eff = 0.0;  // kappa n_b (Eq. 34)
    double A0_eff = 0.0;   // kappa A0 (Eq. 35)
    double K_over_G = 0.0; // 2(1 + nu)/(3(1 - 2 nu))
    double lode_k = 0.0;   // (1 - c_eff)/c_eff, the factor of the B and C terms

    // Convention at kappa = 1: M_c and c are taken from the set as they are. Eq. 33 itself gives
    // c = (3 - sin phi_c)/(3 + sin phi_c), e.g. 0.698 for M_c = 1.3 instead of Table 4's 0.88,
    // so c_eff jumps from about 0.70 (kappa -> 1 from below) to the set's c at kappa = 1; M_c is
    // continuous. Only the extension side (M_e = c M_c) of the surfaces is affected by the jump.
    void prepare() {
        if (roughness < 1.0) {
            const double sin_phi_c = 3.0 * M_c / (6.0 + M_c);
            const double s = std::sin(roughness * std::asin(sin_phi_c));
            M_c_eff = 6.0 * s / (3.0 - s);          // Eq. 33
            const double M_e = 6.0 * s / (3.0 + s); // magnitude of Eq. 33's M_e
            c_eff = M_e / M_c_eff;
        } else {
            M_c_eff = M_c;
            c_eff = c;
        }
        n_b_eff = roughness * n_b;
        A0_eff = roughness * A0;
        K_over_G = 2.0 * (1.0 + nu) / (3.0 * (1.0 - 2.0 * nu));
        lode_k = (1.0 - c_eff) / c_eff;
    }
};

} // namespace ifsim
