#include "fem/element_geometry.hpp"

#include <stdexcept>

#include <fmt/format.h>

#include "fem/element_kernels.hpp"

namespace ifsim::fem {
namespace {

template <int D>
void build(const Mesh& mesh, ElementGeometry& g, const double* displacement) {
    using Tr = ElementTraits<D>;
    using S = Shape<Tr::type>;
    constexpr int nen = Tr::nen;
    const bool reduced = g.integration == Integration::reduced;
    const GaussRule<D> full = gauss_rule<D>(false);
    const int ne = mesh.n_elements();
    g.nip = reduced ? 1 : full.n;
    const auto n_points = static_cast<std::size_t>(ne * g.nip);
    g.dNdx.assign(n_points * nen * D, 0.0);
    g.dV.assign(n_points, 0.0);
    g.ip_coordinates.assign(n_points * D, 0.0);
    g.volume.assign(static_cast<std::size_t>(ne), 0.0);
    if (reduced) {
        g.n_hourglass = Tr::n_hourglass;
        g.hourglass_gamma.assign(static_cast<std::size_t>(ne * Tr::n_hourglass * nen), 0.0);
        g.hourglass_scale.assign(static_cast<std::size_t>(ne), 0.0);
    }
    double X[nen * D];
    double grad[nen * D];
    double N[nen];
    for (int e = 0; e < ne; ++e) {
        gather_coordinates(mesh, e, X, displacement);
        double bbar[nen * D] = {};
        double V = 0.0;
        for (int q = 0; q < full.n; ++q) {
            const double det = physical_gradients<D>(X, full.xi[q].data(), grad);
            if (!(det > 0.0)) {
                throw std::invalid_argument(fmt::format(
                    "element {} is inverted or degenerate (det J = {:.3g} at Gauss point {})", e,
                    det, q));
            }
            const double w = det * full.weight[q];
            V += w;
            if (reduced) {
                for (int k = 0; k < nen * D; ++k) {
                    bbar[k] += grad[k] * w;
                }
                continue;
            }
            const auto p = static_cast<std::size_t>(e * g.nip + q);
            std::copy(grad, grad + nen * D,
                      g.dNdx.begin() + static_cast<std::ptrdiff_t>(p * nen * D));
            g.dV[p] = w;
            S::values(full.xi[q].data(), N);
            for (int a = 0; a < nen; ++a) {
                for (int i = 0; i < D; ++i) {
                    g.ip_coordinates[p * D + static_cast<std::size_t>(i)] += N[a] * X[a * D + i];
                }
            }
        }
        g.volume[static_cast<std::size_t>(e)] = V;
        if (!reduced) {
            continue;
        }
        double sum_b2 = 0.0;
        for (int k = 0; k < nen * D; ++k) {
            bbar[k] /= V;
            sum_b2 += bbar[k] * bbar[k];
        }
        const auto p = static_cast<std::size_t>(e);
        std::copy(bbar, bbar + nen * D, g.dNdx.begin() + static_cast<std::ptrdiff_t>(p * nen * D));
        g.dV[p] = V;
        const double centre[D] = {};
        S::values(centre, N);
        for (int a = 0; a < nen; ++a) {
            for (int i = 0; i < D; ++i) {
                g.ip_coordinates[p * D + static_cast<std::size_t>(i)] += N[a] * X[a * D + i];
            }
        }
        hourglass_vectors<D>(X, bbar, g.hourglass_gamma.data() + p * Tr::n_hourglass * nen);
        g.hourglass_scale[p] = V * sum_b2;
    }
}

} // namespace

void gather_coordinates(const Mesh& mesh, int element, double* X, const double* displacement) {
    const int D = mesh.dim();
    for (int a = 0; a < mesh.nodes_per_element(); ++a) {
        const int n = mesh.node(element, a);
        for (int i = 0; i < D; ++i) {
            X[a * D + i] = mesh.coordinate(n, i);
            if (displacement != nullptr) {
                X[a * D + i] += displacement[n * D + i];
            }
        }
    }
}

ElementGeometry build_geometry(const Mesh& mesh, Integration integration,
                               const double* displacement) {
    ElementGeometry g;
    g.dim = mesh.dim();
    g.nen = mesh.nodes_per_element();
    g.integration = integration;
    if (g.dim == 2) {
        build<2>(mesh, g, displacement);
    } else {
        build<3>(mesh, g, displacement);
    }
    return g;
}

} // namespace ifsim::fem
