#pragma once
// Point kinematics of the updated-Lagrangian continuum ([mesh] kinematics =
// "updated-lagrangian"; docs/fem.md "Large deformation"). An increment is measured on the
// configuration x_n of the last converged increment: G = d du / d x_n, F = I + G, J = det F.
//
// Objective stress update after Hughes & Winget (1980): the velocity gradient of the increment
// on the midpoint configuration, L = G (I + G/2)^-1, gives the strain increment sym L and the
// spin W = skew L; the start state's tensors (stress, intergranular strain, back stress,
// fabric) are turned by R = (I - W/2)^-1 (I + W/2), an exact rotation, before the model runs:
// the Zaremba-Jaumann rate integrated so that a rigid rotation gives sym L = 0 and turns the
// stress exactly. The strain increment the model receives is sym L turned by the half rotation
// R_h (R_h R_h = R): for an objective (isotropic) model this is the symmetric split "turn by
// R_h, integrate, turn by R_h", second order in the step (with sym L alone the stress increment
// lags half a rotation: first order, measured in tests/fem/test_updated_lagrangian.cpp).
//
// Forces on x_n: f_a,i = sum_q P_ij dN_a/dx_n,j dV_n with the first Piola-Kirchhoff stress of
// the increment P = J sigma F^-T (sigma: Cauchy stress on x_{n+1}). The tangent dP/dG is built
// from the model's dsigma/d(sym L) and the exact derivatives of the kinematic map (central
// differences of closed-form functions), taking the model's dependence on its rotated start
// as the identity (exact for linear elasticity, O(|du|) otherwise).

#include <array>

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include "kernels/voigt.hpp"

namespace ifsim::fem {

using Mat3 = Eigen::Matrix3d;

struct IncrementKinematics {
    Mat3 F = Mat3::Identity();
    Mat3 F_inv_T = Mat3::Identity();
    double J = 1.0;
    Sym<double> deps{}; // R_h sym(L) R_h^T, tensor components in Voigt order
    Mat3 R = Mat3::Identity();
};

inline Mat3 as_matrix(const Sym<double>& s) {
    Mat3 m;
    m << s[0], s[3], s[4], s[3], s[1], s[5], s[4], s[5], s[2];
    return m;
}

inline Sym<double> as_voigt(const Mat3& m) {
    return {m(0, 0),
            m(1, 1),
            m(2, 2),
            0.5 * (m(0, 1) + m(1, 0)),
            0.5 * (m(0, 2) + m(2, 0)),
            0.5 * (m(1, 2) + m(2, 1))};
}

// R s R^T of a symmetric tensor in Voigt order (tensor components).
inline Sym<double> rotate(const Mat3& R, const Sym<double>& s) {
    return as_voigt(R * as_matrix(s) * R.transpose());
}

inline IncrementKinematics increment_kinematics(const Mat3& G) {
    IncrementKinematics k;
    k.F = Mat3::Identity() + G;
    k.J = k.F.determinant();
    k.F_inv_T = k.F.inverse().transpose();
    const Mat3 L = G * (Mat3::Identity() + 0.5 * G).inverse();
    const Mat3 W = 0.5 * (L - L.transpose());
    k.R = (Mat3::Identity() - 0.5 * W).inverse() * (Mat3::Identity() + 0.5 * W);
    // The half rotation: the square root of the unit quaternion of R, (1 + q) / |1 + q|.
    Eigen::Quaterniond q(k.R);
    if (q.w() < 0.0) {
        q.coeffs() *= -1.0;
    }
    Eigen::Quaterniond half(1.0 + q.w(), q.x(), q.y(), q.z());
    half.normalize();
    const Mat3 Rh = half.toRotationMatrix();
    k.deps = as_voigt(Rh * (0.5 * (L + L.transpose())) * Rh.transpose());
    return k;
}

// P = J sigma F^-T.
inline Mat3 first_piola(const Sym<double>& sigma, const IncrementKinematics& k) {
    return k.J * as_matrix(sigma) * k.F_inv_T;
}

// dP_ij / dG_kl of the active D x D blocks (row i * D + j, column k * D + l) at the increment
// G with trial stress sigma, committed (unturned) stress sigma_n and the model's tangent Dm
// (ncomp x ncomp, row-major, active tensor components `comps` of the Voigt six).
template <int D, std::size_t NC>
Eigen::Matrix<double, D * D, D * D>
first_piola_tangent(const Mat3& G, const Sym<double>& sigma, const Sym<double>& sigma_n,
                    const double* Dm, const std::array<int, NC>& comps) {
    Eigen::Matrix<double, D * D, D * D> A;
    const IncrementKinematics k0 = increment_kinematics(G);
    const Sym<double> turned0 = rotate(k0.R, sigma_n);
    const double h = 1.0e-6;
    for (int c = 0; c < D * D; ++c) {
        Mat3 P[2];
        for (int side = 0; side < 2; ++side) {
            Mat3 Gp = G;
            Gp(c / D, c % D) += side == 0 ? h : -h;
            const IncrementKinematics kp = increment_kinematics(Gp);
            // sigma(G') ~ sigma + Dm : (deps' - deps) + (R' sigma_n R'^T - R sigma_n R^T)
            Sym<double> s = sigma;
            const Sym<double> turned = rotate(kp.R, sigma_n);
            for (int j = 0; j < 6; ++j) {
                s[static_cast<std::size_t>(j)] +=
                    turned[static_cast<std::size_t>(j)] - turned0[static_cast<std::size_t>(j)];
            }
            for (std::size_t r = 0; r < NC; ++r) {
                double ds = 0.0;
                for (std::size_t cc = 0; cc < NC; ++cc) {
                    const auto v = static_cast<std::size_t>(comps[cc]);
                    ds += Dm[r * NC + cc] * (kp.deps[v] - k0.deps[v]);
                }
                s[static_cast<std::size_t>(comps[r])] += ds;
            }
            P[side] = first_piola(s, kp);
        }
        for (int r = 0; r < D * D; ++r) {
            A(r, c) = (P[0](r / D, r % D) - P[1](r / D, r % D)) / (2.0 * h);
        }
    }
    return A;
}

} // namespace ifsim::fem

#include "fem/element_kernels.hpp"

namespace ifsim::fem {

// f_a,i += dV P_ij dN_a/dx_j (dN/dx and dV on the configuration x_n).
template <int D>
void add_piola_force(const double* dNdx, const Mat3& P, double dV, double* f) {
    constexpr int nen = ElementTraits<D>::nen;
    for (int a = 0; a < nen; ++a) {
        for (int i = 0; i < D; ++i) {
            double v = 0.0;
            for (int j = 0; j < D; ++j) {
                v += P(i, j) * dNdx[a * D + j];
            }
            f[a * D + i] += dV * v;
        }
    }
}

// K(a i, b k) += dV dN_a/dx_j A(i j, k l) dN_b/dx_l.
template <int D>
void add_piola_tangent(const double* dNdx, const Eigen::Matrix<double, D * D, D * D>& A, double dV,
                       Eigen::Matrix<double, ElementTraits<D>::ndof, ElementTraits<D>::ndof>& K) {
    constexpr int nen = ElementTraits<D>::nen;
    for (int a = 0; a < nen; ++a) {
        for (int b = 0; b < nen; ++b) {
            for (int i = 0; i < D; ++i) {
                for (int k = 0; k < D; ++k) {
                    double v = 0.0;
                    for (int j = 0; j < D; ++j) {
                        for (int l = 0; l < D; ++l) {
                            v += dNdx[a * D + j] * A(i * D + j, k * D + l) * dNdx[b * D + l];
                        }
                    }
                    K(a * D + i, b * D + k) += dV * v;
                }
            }
        }
    }
}

// Displacement-increment gradient G_ij = d du_i / d x_j of one point (zero rows and columns
// beyond D).
template <int D>
Mat3 increment_gradient(const double* dNdx, const double* du) {
    Mat3 G = Mat3::Zero();
    for (int a = 0; a < ElementTraits<D>::nen; ++a) {
        for (int i = 0; i < D; ++i) {
            for (int j = 0; j < D; ++j) {
                G(i, j) += du[a * D + i] * dNdx[a * D + j];
            }
        }
    }
    return G;
}

} // namespace ifsim::fem
