#include "io/element_test/element_orientation.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "fem/shape_functions.hpp"

namespace ifsim::io {

namespace {

// det(dx/dxi) at the natural coordinates xi of an element of type E.
template <fem::ElementType E>
double jacobian(std::span<const int> nodes, const std::vector<double>& x, const double* xi) {
    using S = fem::Shape<E>;
    constexpr int d = S::dim;
    std::array<double, S::nen * d> dN{};
    S::gradients(xi, dN.data());
    std::array<double, d * d> J{}; // J[i * d + j] = d x_i / d xi_j
    for (int a = 0; a < S::nen; ++a) {
        const auto base = static_cast<std::size_t>(nodes[static_cast<std::size_t>(a)] * d);
        for (int i = 0; i < d; ++i) {
            for (int j = 0; j < d; ++j) {
                J[static_cast<std::size_t>(i * d + j)] +=
                    x[base + static_cast<std::size_t>(i)] * dN[static_cast<std::size_t>(a * d + j)];
            }
        }
    }
    if constexpr (d == 2) {
        return J[0] * J[3] - J[1] * J[2];
    } else {
        return J[0] * (J[4] * J[8] - J[5] * J[7]) - J[1] * (J[3] * J[8] - J[5] * J[6]) +
               J[2] * (J[3] * J[7] - J[4] * J[6]);
    }
}

template <fem::ElementType E>
Orientation orient(std::span<int> nodes, const std::vector<double>& x) {
    using S = fem::Shape<E>;
    const double centre[3] = {0.0, 0.0, 0.0};
    Orientation result = Orientation::kept;
    double det = jacobian<E>(nodes, x, centre);
    if (det < 0.0) {
        if constexpr (S::dim == 2) {
            std::reverse(nodes.begin() + 1, nodes.end());
        } else {
            std::swap_ranges(nodes.begin(), nodes.begin() + 4, nodes.begin() + 4);
        }
        det = -det;
        result = Orientation::mirrored;
    }
    if (!(det > 0.0)) {
        return Orientation::invalid;
    }
    // Positive at every node, relative to the centre's (round-off of a collapsed corner).
    for (const auto& xi : S::node_xi) {
        if (!(jacobian<E>(nodes, x, xi) > 1.0e-12 * det)) {
            return Orientation::invalid;
        }
    }
    return result;
}

} // namespace

Orientation orient_element(fem::ElementType type, std::span<int> nodes,
                           const std::vector<double>& coordinates) {
    return type == fem::ElementType::quad4 ? orient<fem::ElementType::quad4>(nodes, coordinates)
                                           : orient<fem::ElementType::hex8>(nodes, coordinates);
}

} // namespace ifsim::io
