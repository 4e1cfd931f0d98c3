#pragma once
// The interface point's stress at the start of an interface test (paper §5 and Appendix C), in
// local axes (1 = normal, 2 = t1, 3 = t2) and the layout of Eq. 17: [sigma_N, sigma_p1,
// sigma_p2, tau_1, tau_2, 0].
//
//   novel, Stutz from the continuum:  sigma_N = t_N = sample s11, sigma_p1 = s22, sigma_p2 = s33
//   Stutz from the normal contact:    sigma_N = sigma_p1 = sigma_p2 = t_N (what Abaqus allows)
// The shear stresses are the sample's s12 and s13 in every case (the interface and the sample
// carry the same shear stress); the in-plane shear of Eq. 17 is zero.

#include <array>

namespace ifsim::io {

enum class InterfaceStressStart { continuum, normal_contact };

inline std::array<double, 6> initial_interface_stress(const std::array<double, 6>& sample_stress,
                                                      InterfaceStressStart start) {
    const double t_N = sample_stress[0];
    const bool from_contact = start == InterfaceStressStart::normal_contact;
    return {t_N,
            from_contact ? t_N : sample_stress[1],
            from_contact ? t_N : sample_stress[2],
            sample_stress[3],
            sample_stress[4],
            0.0};
}

} // namespace ifsim::io
