#include "fem/stress_extrapolation.hpp"

#include <cmath>
#include <stdexcept>

#include "fem/shape_functions.hpp"

namespace ifsim::fem {

Voigt6 extrapolate_stress(int dim, std::span<const Voigt6> point_stress, const double* xi) {
    Voigt6 out{};
    if (point_stress.size() == 1) {
        return point_stress[0]; // reduced integration: constant stress (Eq. 14 with ngp = 1)
    }
    const std::size_t n = std::size_t{1} << dim;
    if (point_stress.size() != n || (dim != 2 && dim != 3)) {
        throw std::invalid_argument("extrapolate_stress: expected 1 or 2^dim point stresses");
    }
    const double r3 = std::sqrt(3.0);
    for (std::size_t q = 0; q < n; ++q) {
        double N = 1.0; // Eq. 14: N_q at the stretched coordinates sqrt(3) xi
        for (int i = 0; i < dim; ++i) {
            const double sign = ((q >> i) & 1U) ? 1.0 : -1.0;
            N *= 0.5 * (1.0 + sign * r3 * xi[i]);
        }
        for (int c = 0; c < 6; ++c) {
            out[static_cast<std::size_t>(c)] += N * point_stress[q][static_cast<std::size_t>(c)];
        }
    }
    return out;
}

std::array<double, 2> quad4_face_point(int local_face, double s) {
    const auto nodes = face_nodes(ElementType::quad4, local_face);
    const auto& a = Shape<ElementType::quad4>::node_xi[nodes[0]];
    const auto& b = Shape<ElementType::quad4>::node_xi[nodes[1]];
    const double Na = 0.5 * (1.0 - s);
    const double Nb = 0.5 * (1.0 + s);
    return {Na * a[0] + Nb * b[0], Na * a[1] + Nb * b[1]};
}

Voigt6 average_stress(std::span<const Voigt6> extrapolated) {
    Voigt6 out{};
    for (const auto& s : extrapolated) {
        for (std::size_t c = 0; c < 6; ++c) {
            out[c] += s[c] / static_cast<double>(extrapolated.size());
        }
    }
    return out;
}

Voigt6 rotate_to_frame(const Voigt6& s, const std::array<double, 3>& n,
                       const std::array<double, 3>& t1, const std::array<double, 3>& t2) {
    const double S[3][3] = {{s[0], s[3], s[4]}, {s[3], s[1], s[5]}, {s[4], s[5], s[2]}};
    const std::array<double, 3>* a[3] = {&n, &t1, &t2}; // alpha_ij = e'_i . e_j (Eq. 16)
    double R[3][3]{};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            double v = 0.0;
            for (int k = 0; k < 3; ++k) {
                for (int l = 0; l < 3; ++l) {
                    v += (*a[i])[static_cast<std::size_t>(k)] * S[k][l] *
                         (*a[j])[static_cast<std::size_t>(l)];
                }
            }
            R[i][j] = v;
        }
    }
    return {R[0][0], R[1][1], R[2][2], R[0][1], R[0][2], R[1][2]};
}

} // namespace ifsim::fem
