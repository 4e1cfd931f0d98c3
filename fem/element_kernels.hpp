#pragma once
// Element-level kernels of the small-strain continuum elements quad4 (plane strain) and hex8.
// Written over the dimension D (nen = 2^D nodes); per element they read the nodal data and
// the integration-point data (gradients, weights, stress, tangent) and write the element
// vector or matrix. No allocation.
//
// Strains are TENSOR components in Voigt order 11 22 33 12 13 23 (eps_12 = (u1,2 + u2,1)/2).
// The element works with the ncomp = 3 (2D: 11 22 12) or 6 (3D) active components; in plane
// strain eps_33 = eps_13 = eps_23 = 0 and sigma_33 does no work. The virtual work
// sigma : delta eps counts the shear components twice, so with B mapping displacements to
// tensor strains: f = B^T W sigma dV and K = B^T W D B dV with W = diag(1, 1, [1,] 2, [2, 2]).

#include <array>

#include <Eigen/Dense>

#include "fem/shape_functions.hpp"
#include "kernels/voigt.hpp"

namespace ifsim::fem {

template <int D>
struct ElementTraits {
    static constexpr int dim = D;
    static constexpr int nen = 1 << D;
    static constexpr int ndof = nen * D;
    static constexpr int ncomp = D == 2 ? 3 : 6;
    static constexpr ElementType type = D == 2 ? ElementType::quad4 : ElementType::hex8;
    // Voigt index (of the 6) of each active strain component.
    static constexpr std::array<int, ncomp> voigt_of() {
        if constexpr (D == 2) {
            return {0, 1, 3};
        } else {
            return {0, 1, 2, 3, 4, 5};
        }
    }
    // Number of hourglass base vectors (Flanagan & Belytschko 1981).
    static constexpr int n_hourglass = D == 2 ? 1 : 4;
};

// Physical gradients dN_a/dx_i (node-major) at natural point xi from nodal coordinates X
// (node-major). Returns det J (paper Eq. A2); <= 0 means an inverted or degenerate element.
template <int D>
double physical_gradients(const double* X, const double* xi, double* dNdx) {
    using S = Shape<ElementTraits<D>::type>;
    constexpr int nen = ElementTraits<D>::nen;
    double dN[nen * D];
    S::gradients(xi, dN);
    Eigen::Matrix<double, D, D> J = Eigen::Matrix<double, D, D>::Zero(); // J_ij = dx_i/dxi_j
    for (int a = 0; a < nen; ++a) {
        for (int i = 0; i < D; ++i) {
            for (int j = 0; j < D; ++j) {
                J(i, j) += X[a * D + i] * dN[a * D + j];
            }
        }
    }
    const double det = J.determinant();
    if (!(det > 0.0)) {
        return det;
    }
    const Eigen::Matrix<double, D, D> Jinv = J.inverse();
    for (int a = 0; a < nen; ++a) {
        for (int i = 0; i < D; ++i) {
            double s = 0.0;
            for (int j = 0; j < D; ++j) {
                s += dN[a * D + j] * Jinv(j, i);
            }
            dNdx[a * D + i] = s;
        }
    }
    return det;
}

// Strain (6 tensor components) of the nodal displacements u (node-major) at one point.
template <int D>
Sym<double> strain_at(const double* dNdx, const double* u) {
    constexpr int nen = ElementTraits<D>::nen;
    double H[3][3] = {}; // displacement gradient H_ij = du_i/dx_j
    for (int a = 0; a < nen; ++a) {
        for (int i = 0; i < D; ++i) {
            for (int j = 0; j < D; ++j) {
                H[i][j] += u[a * D + i] * dNdx[a * D + j];
            }
        }
    }
    return {H[0][0],
            H[1][1],
            H[2][2],
            0.5 * (H[0][1] + H[1][0]),
            0.5 * (H[0][2] + H[2][0]),
            0.5 * (H[1][2] + H[2][1])};
}

// Strain-displacement matrix of the active tensor components.
template <int D>
Eigen::Matrix<double, ElementTraits<D>::ncomp, ElementTraits<D>::ndof>
strain_matrix(const double* dNdx) {
    using Tr = ElementTraits<D>;
    Eigen::Matrix<double, Tr::ncomp, Tr::ndof> B = decltype(B)::Zero();
    for (int a = 0; a < Tr::nen; ++a) {
        const double* g = dNdx + a * D;
        const int c = a * D;
        if constexpr (D == 2) {
            B(0, c) = g[0];
            B(1, c + 1) = g[1];
            B(2, c) = 0.5 * g[1];
            B(2, c + 1) = 0.5 * g[0];
        } else {
            B(0, c) = g[0];
            B(1, c + 1) = g[1];
            B(2, c + 2) = g[2];
            B(3, c) = 0.5 * g[1];
            B(3, c + 1) = 0.5 * g[0];
            B(4, c) = 0.5 * g[2];
            B(4, c + 2) = 0.5 * g[0];
            B(5, c + 1) = 0.5 * g[2];
            B(5, c + 2) = 0.5 * g[1];
        }
    }
    return B;
}

// Weight of each active component in sigma : eps (shear counted twice).
template <int D>
constexpr double shear_weight(int comp) {
    return ElementTraits<D>::voigt_of()[static_cast<std::size_t>(comp)] >= 3 ? 2.0 : 1.0;
}

// f_a,i += dV sigma_ij dN_a/dx_j (internal force of one integration point).
template <int D>
void add_internal_force(const double* dNdx, const Sym<double>& s, double dV, double* f) {
    constexpr int nen = ElementTraits<D>::nen;
    const double S[3][3] = {{s[0], s[3], s[4]}, {s[3], s[1], s[5]}, {s[4], s[5], s[2]}};
    for (int a = 0; a < nen; ++a) {
        for (int i = 0; i < D; ++i) {
            double v = 0.0;
            for (int j = 0; j < D; ++j) {
                v += S[i][j] * dNdx[a * D + j];
            }
            f[a * D + i] += dV * v;
        }
    }
}

// K += B^T W Dm B dV with Dm the ncomp x ncomp tangent (row-major, d sigma_r / d eps_c of the
// active tensor components).
template <int D>
void add_tangent(const double* dNdx, const double* Dm, double dV,
                 Eigen::Matrix<double, ElementTraits<D>::ndof, ElementTraits<D>::ndof>& K) {
    using Tr = ElementTraits<D>;
    const auto B = strain_matrix<D>(dNdx);
    Eigen::Matrix<double, Tr::ncomp, Tr::ncomp> WD;
    for (int r = 0; r < Tr::ncomp; ++r) {
        for (int c = 0; c < Tr::ncomp; ++c) {
            WD(r, c) = shear_weight<D>(r) * Dm[r * Tr::ncomp + c] * dV;
        }
    }
    const Eigen::Matrix<double, Tr::ncomp, Tr::ndof> WDB = WD * B;
    K.noalias() += B.transpose() * WDB;
}

// Hourglass base vectors gamma_alpha,a (Flanagan & Belytschko 1981):
// gamma = (h - (h . x_j) bbar_j) / 2^D with h the products of natural coordinates at the nodes
// (xi eta in 2D; eta zeta, xi zeta, xi eta, xi eta zeta in 3D) and bbar the volume-averaged
// gradients. gamma is orthogonal to every linear displacement field on any geometry, so the
// hourglass forces vanish in the patch test.
template <int D>
void hourglass_vectors(const double* X, const double* bbar, double* gamma) {
    using Tr = ElementTraits<D>;
    using S = Shape<Tr::type>;
    for (int alpha = 0; alpha < Tr::n_hourglass; ++alpha) {
        double h[Tr::nen];
        for (int a = 0; a < Tr::nen; ++a) {
            const double* n = S::node_xi[a];
            if constexpr (D == 2) {
                h[a] = n[0] * n[1];
            } else {
                h[a] = alpha == 0   ? n[1] * n[2]
                       : alpha == 1 ? n[0] * n[2]
                       : alpha == 2 ? n[0] * n[1]
                                    : n[0] * n[1] * n[2];
            }
        }
        double hx[D] = {};
        for (int a = 0; a < Tr::nen; ++a) {
            for (int j = 0; j < D; ++j) {
                hx[j] += h[a] * X[a * D + j];
            }
        }
        for (int a = 0; a < Tr::nen; ++a) {
            double g = h[a];
            for (int j = 0; j < D; ++j) {
                g -= hx[j] * bbar[a * D + j];
            }
            gamma[alpha * Tr::nen + a] = g / double(Tr::nen);
        }
    }
}

// Hourglass force f_a,i += k sum_alpha gamma_alpha,a q_alpha,i with q = gamma . u (u the total
// nodal displacements), and its stiffness K(a i, b k) += k sum_alpha gamma_a gamma_b delta_ik.
template <int D>
void add_hourglass_force(const double* gamma, double k, const double* u, double* f) {
    using Tr = ElementTraits<D>;
    for (int alpha = 0; alpha < Tr::n_hourglass; ++alpha) {
        const double* g = gamma + alpha * Tr::nen;
        double q[D] = {};
        for (int b = 0; b < Tr::nen; ++b) {
            for (int i = 0; i < D; ++i) {
                q[i] += g[b] * u[b * D + i];
            }
        }
        for (int a = 0; a < Tr::nen; ++a) {
            for (int i = 0; i < D; ++i) {
                f[a * D + i] += k * g[a] * q[i];
            }
        }
    }
}
template <int D>
void add_hourglass_tangent(
    const double* gamma, double k,
    Eigen::Matrix<double, ElementTraits<D>::ndof, ElementTraits<D>::ndof>& K) {
    using Tr = ElementTraits<D>;
    for (int alpha = 0; alpha < Tr::n_hourglass; ++alpha) {
        const double* g = gamma + alpha * Tr::nen;
        for (int a = 0; a < Tr::nen; ++a) {
            for (int b = 0; b < Tr::nen; ++b) {
                const double v = k * g[a] * g[b];
                for (int i = 0; i < D; ++i) {
                    K(a * D + i, b * D + i) += v;
                }
            }
        }
    }
}

} // namespace ifsim::fem
