#include "fem/loads.hpp"

#include "fem/element_geometry.hpp"
#include "fem/element_kernels.hpp"

namespace ifsim::fem {
namespace {

template <int D>
void add_gravity(const Mesh& mesh, const std::vector<double>& density, std::vector<double>& f) {
    using Tr = ElementTraits<D>;
    using S = Shape<Tr::type>;
    const GaussRule<D> rule = gauss_rule<D>(false);
    double X[Tr::nen * D];
    double grad[Tr::nen * D];
    double N[Tr::nen];
    for (int e = 0; e < mesh.n_elements(); ++e) {
        const double rho = density[static_cast<std::size_t>(e)];
        if (rho == 0.0) {
            continue;
        }
        gather_coordinates(mesh, e, X);
        for (int q = 0; q < rule.n; ++q) {
            const double det = physical_gradients<D>(X, rule.xi[q].data(), grad);
            S::values(rule.xi[q].data(), N);
            for (int a = 0; a < Tr::nen; ++a) {
                f[static_cast<std::size_t>(mesh.node(e, a) * D + D - 1)] -=
                    N[a] * rho * det * rule.weight[q];
            }
        }
    }
}

} // namespace

std::vector<double> unit_gravity_forces(const Mesh& mesh, const std::vector<double>& density) {
    std::vector<double> f(static_cast<std::size_t>(mesh.n_nodes() * mesh.dim()), 0.0);
    if (mesh.dim() == 2) {
        add_gravity<2>(mesh, density, f);
    } else {
        add_gravity<3>(mesh, density, f);
    }
    return f;
}

std::vector<double> unit_pressure_forces(const Mesh& mesh, const std::string& face_set) {
    const int D = mesh.dim();
    std::vector<double> f(static_cast<std::size_t>(mesh.n_nodes() * D), 0.0);
    for (const FaceRef& face : mesh.face_set(face_set)) {
        const auto local = face_nodes(mesh.type, face.local_face);
        int nodes[4];
        for (std::size_t k = 0; k < local.size(); ++k) {
            nodes[k] = mesh.node(face.element, local[k]);
        }
        const auto add = [&](int node, int i, double v) {
            f[static_cast<std::size_t>(node * D + i)] += v;
        };
        if (D == 2) {
            // x_,xi = (x_b - x_a) / 2 and int N_a dxi = 1: f_a = -(t_y, -t_x) / 2.
            const double tx = mesh.coordinate(nodes[1], 0) - mesh.coordinate(nodes[0], 0);
            const double ty = mesh.coordinate(nodes[1], 1) - mesh.coordinate(nodes[0], 1);
            for (int k = 0; k < 2; ++k) {
                add(nodes[k], 0, -0.5 * ty);
                add(nodes[k], 1, 0.5 * tx);
            }
            continue;
        }
        // Bilinear face, 2x2 Gauss: n dA = x_,xi x x_,eta dxi deta.
        const GaussRule<2> rule = gauss_rule<2>(false);
        double X[4 * 3];
        for (int k = 0; k < 4; ++k) {
            for (int i = 0; i < 3; ++i) {
                X[k * 3 + i] = mesh.coordinate(nodes[k], i);
            }
        }
        for (int q = 0; q < rule.n; ++q) {
            double N[4];
            double dN[8];
            Shape<ElementType::quad4>::values(rule.xi[q].data(), N);
            Shape<ElementType::quad4>::gradients(rule.xi[q].data(), dN);
            double a[3] = {};
            double b[3] = {};
            for (int k = 0; k < 4; ++k) {
                for (int i = 0; i < 3; ++i) {
                    a[i] += dN[k * 2 + 0] * X[k * 3 + i];
                    b[i] += dN[k * 2 + 1] * X[k * 3 + i];
                }
            }
            const double n[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                                 a[0] * b[1] - a[1] * b[0]};
            for (int k = 0; k < 4; ++k) {
                for (int i = 0; i < 3; ++i) {
                    add(nodes[k], i, -N[k] * n[i] * rule.weight[q]);
                }
            }
        }
    }
    return f;
}

} // namespace ifsim::fem
