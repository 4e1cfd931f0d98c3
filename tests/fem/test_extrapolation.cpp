// Stress extrapolation to the surface (Eq. 14) and rotation into the contact frame
// (Eqs. 15, 16).
#include <gtest/gtest.h>

#include <cmath>

#include "fem/shape_functions.hpp"
#include "fem/stress_extrapolation.hpp"

namespace {

using namespace ifsim::fem;

// A field linear in each natural coordinate (multilinear), component-dependent.
Voigt6 field(int dim, const double* xi) {
    Voigt6 s{};
    for (int c = 0; c < 6; ++c) {
        double v = -100.0 - 10.0 * c + (3.0 + c) * xi[0] - 2.0 * c * xi[1] + 0.5 * xi[0] * xi[1];
        if (dim == 3) {
            v += 4.0 * xi[2] - xi[0] * xi[2] + 0.25 * xi[0] * xi[1] * xi[2];
        }
        s[static_cast<std::size_t>(c)] = v;
    }
    return s;
}

template <int Dim>
std::vector<Voigt6> gauss_values() {
    const auto rule = gauss_rule<Dim>(false);
    std::vector<Voigt6> v;
    for (int q = 0; q < rule.n; ++q) {
        v.push_back(field(Dim, rule.xi[static_cast<std::size_t>(q)].data()));
    }
    return v;
}

TEST(StressExtrapolation, MultilinearFieldExactForFullIntegration2D) {
    const auto gp = gauss_values<2>();
    for (int f = 0; f < 4; ++f) {
        for (const double s : {-1.0, -0.577, 0.0, 0.3, 1.0}) {
            const auto xi = quad4_face_point(f, s);
            const auto e = extrapolate_stress(2, gp, xi.data());
            const auto ref = field(2, xi.data());
            for (std::size_t c = 0; c < 6; ++c) {
                EXPECT_NEAR(e[c], ref[c], 1e-12) << "face " << f << " s " << s;
            }
        }
    }
    // Face 2 runs from node 2 (1, 1) to node 3 (-1, 1).
    const auto start = quad4_face_point(2, -1.0);
    EXPECT_EQ(start[0], 1.0);
    EXPECT_EQ(start[1], 1.0);
    const auto end = quad4_face_point(2, 1.0);
    EXPECT_EQ(end[0], -1.0);
}

TEST(StressExtrapolation, TrilinearFieldExactForFullIntegration3D) {
    const auto gp = gauss_values<3>();
    for (const std::array<double, 3> xi :
         {std::array<double, 3>{1, 1, 1}, {-1, 0.2, 1}, {0.5, -1, -0.7}, {-1, -1, -1}}) {
        const auto e = extrapolate_stress(3, gp, xi.data());
        const auto ref = field(3, xi.data());
        for (std::size_t c = 0; c < 6; ++c) {
            EXPECT_NEAR(e[c], ref[c], 1e-12);
        }
    }
}

TEST(StressExtrapolation, UniformAndReducedAndAverage) {
    const Voigt6 u{-100, -50, -60, 10, 0, 0};
    const std::vector<Voigt6> four(4, u);
    const double xi[2] = {1.0, -0.3};
    const auto e = extrapolate_stress(2, four, xi);
    for (std::size_t c = 0; c < 6; ++c) {
        EXPECT_NEAR(e[c], u[c], 1e-12);
    }
    const std::vector<Voigt6> one{u};
    EXPECT_EQ(extrapolate_stress(2, one, xi), u); // reduced: the constant point stress
    const std::vector<Voigt6> three(3, u);
    EXPECT_THROW(extrapolate_stress(2, three, xi), std::invalid_argument);
    // A node between two elements: the mean of both extrapolations (Eq. 14 remark).
    const Voigt6 a{-100, 0, 0, 0, 0, 0};
    const Voigt6 b{-200, 0, 0, 4, 0, 0};
    const std::vector<Voigt6> both{a, b};
    const auto m = average_stress(both);
    EXPECT_DOUBLE_EQ(m[0], -150.0);
    EXPECT_DOUBLE_EQ(m[3], 2.0);
}

TEST(StressExtrapolation, RotationIntoFrame) {
    // Uniaxial stress along n: only the local normal component.
    const double c = std::cos(0.3);
    const double s = std::sin(0.3);
    const std::array<double, 3> n{c, s, 0};
    const std::array<double, 3> t1{-s, c, 0};
    const std::array<double, 3> t2{0, 0, 1};
    const double p = -80.0;
    const Voigt6 uni{p * c * c, p * s * s, 0, p * c * s, 0, 0};
    const auto l = rotate_to_frame(uni, n, t1, t2);
    EXPECT_NEAR(l[0], p, 1e-12);
    for (std::size_t k = 1; k < 6; ++k) {
        EXPECT_NEAR(l[k], 0.0, 1e-12);
    }
    // Objectivity: rotating the stress and the frame together leaves the local components.
    const Voigt6 g{-120, -70, -90, 15, -5, 8};
    const std::array<double, 3> e1{1, 0, 0}, e2{0, 1, 0}, e3{0, 0, 1};
    const auto ref = rotate_to_frame(g, e1, e2, e3);
    for (std::size_t k = 0; k < 6; ++k) {
        EXPECT_NEAR(ref[k], g[k], 1e-12);
    }
    // sigma_rot = Q sigma Q^T with Q the rotation taking e_i to (n, t1, t2).
    const double Q[3][3] = {{c, -s, 0}, {s, c, 0}, {0, 0, 1}};
    const double S[3][3] = {{g[0], g[3], g[4]}, {g[3], g[1], g[5]}, {g[4], g[5], g[2]}};
    double R[3][3]{};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            for (int k = 0; k < 3; ++k) {
                for (int m = 0; m < 3; ++m) {
                    R[i][j] += Q[i][k] * S[k][m] * Q[j][m];
                }
            }
        }
    }
    const Voigt6 rotated{R[0][0], R[1][1], R[2][2], R[0][1], R[0][2], R[1][2]};
    const auto l2 = rotate_to_frame(rotated, n, t1, t2);
    for (std::size_t k = 0; k < 6; ++k) {
        EXPECT_NEAR(l2[k], g[k], 1e-11);
    }
    EXPECT_NEAR(l2[0] + l2[1] + l2[2], g[0] + g[1] + g[2], 1e-11);
}

} // namespace
