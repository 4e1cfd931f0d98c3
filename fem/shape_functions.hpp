#pragma once
// Isoparametric shape functions of quad4 and hex8 (paper Eq. A1) and their Gauss rules
// (Eq. A8). Gradients are stored node-major: dN[a * dim + i] = dN_a / dxi_i.

#include <array>
#include <cmath>

#include "fem/mesh.hpp"

namespace ifsim::fem {

template <ElementType E>
struct Shape;

template <>
struct Shape<ElementType::quad4> {
    static constexpr int dim = 2;
    static constexpr int nen = 4;
    // Natural coordinates of the nodes.
    static constexpr double node_xi[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};

    static void values(const double* xi, double* N) {
        for (int a = 0; a < nen; ++a) {
            N[a] = 0.25 * (1.0 + node_xi[a][0] * xi[0]) * (1.0 + node_xi[a][1] * xi[1]);
        }
    }
    static void gradients(const double* xi, double* dN) {
        for (int a = 0; a < nen; ++a) {
            const double sx = node_xi[a][0];
            const double sy = node_xi[a][1];
            dN[a * 2 + 0] = 0.25 * sx * (1.0 + sy * xi[1]);
            dN[a * 2 + 1] = 0.25 * sy * (1.0 + sx * xi[0]);
        }
    }
};

template <>
struct Shape<ElementType::hex8> {
    static constexpr int dim = 3;
    static constexpr int nen = 8;
    static constexpr double node_xi[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                             {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};

    static void values(const double* xi, double* N) {
        for (int a = 0; a < nen; ++a) {
            N[a] = 0.125 * (1.0 + node_xi[a][0] * xi[0]) * (1.0 + node_xi[a][1] * xi[1]) *
                   (1.0 + node_xi[a][2] * xi[2]);
        }
    }
    static void gradients(const double* xi, double* dN) {
        for (int a = 0; a < nen; ++a) {
            const double fx = 1.0 + node_xi[a][0] * xi[0];
            const double fy = 1.0 + node_xi[a][1] * xi[1];
            const double fz = 1.0 + node_xi[a][2] * xi[2];
            dN[a * 3 + 0] = 0.125 * node_xi[a][0] * fy * fz;
            dN[a * 3 + 1] = 0.125 * node_xi[a][1] * fx * fz;
            dN[a * 3 + 2] = 0.125 * node_xi[a][2] * fx * fy;
        }
    }
};

// Tensor-product Gauss rule with 2 points per direction (exact for the trilinear volume and
// for the integrals of the shape-function gradients), or the 1-point rule at the centre.
template <int Dim>
struct GaussRule {
    static constexpr int max_points = 1 << Dim;
    int n = 0;
    std::array<std::array<double, Dim>, max_points> xi{};
    std::array<double, max_points> weight{};
};

template <int Dim>
GaussRule<Dim> gauss_rule(bool reduced) {
    GaussRule<Dim> r;
    if (reduced) {
        r.n = 1;
        r.weight[0] = double(1 << Dim);
        return r;
    }
    const double g = 1.0 / std::sqrt(3.0);
    r.n = 1 << Dim;
    for (int q = 0; q < r.n; ++q) {
        for (int i = 0; i < Dim; ++i) {
            r.xi[q][i] = ((q >> i) & 1) ? g : -g;
        }
        r.weight[q] = 1.0;
    }
    return r;
}

} // namespace ifsim::fem
