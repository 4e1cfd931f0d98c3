// The updated-Lagrangian passes of ContinuumAssembly (fem/finite_strain.hpp): geometry of the
// increment's start configuration, midpoint strain increments with the Hughes-Winget turn of
// the material points' start, Piola forces and their tangents.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "engine/parallel_chunks.hpp"
#include "fem/continuum_assembly.hpp"
#include "fem/continuum_force_loop.hpp"
#include "fem/continuum_set_data.hpp"
#include "fem/finite_strain.hpp"

namespace ifsim::fem {
namespace {

// The increment gradient G of point q of element e as strains_ul stored it (row-major).
Mat3 stored_gradient(const std::vector<double>& all, std::size_t e, int q, int nip) {
    const double* g =
        all.data() + 9 * (e * static_cast<std::size_t>(nip) + static_cast<std::size_t>(q));
    return Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(g);
}

} // namespace

// Whether the element, moved by its increment ue from the configuration of the increment's
// start, has det J <= 0 at one of its full Gauss points (the check build_geometry makes for
// the next increment's configuration).
template <int D>
bool ContinuumAssembly::inverted_at_gauss_points(const Mesh& mesh, int e, const double* ue) const {
    constexpr int nen = ElementTraits<D>::nen;
    double X[nen * D];
    gather_coordinates(mesh, e, X, configured_u_.data());
    for (int k = 0; k < nen * D; ++k) {
        X[k] += ue[k];
    }
    const GaussRule<D> rule = gauss_rule<D>(false);
    double grad[nen * D];
    for (int q = 0; q < rule.n; ++q) {
        if (!(physical_gradients<D>(X, rule.xi[q].data(), grad) > 0.0)) {
            return true;
        }
    }
    return false;
}

void ContinuumAssembly::begin_increment(const Mesh& mesh, std::span<const double> u) {
    if (settings_.kinematics != Kinematics::updated_lagrangian) {
        return;
    }
    if (std::equal(u.begin(), u.end(), configured_u_.begin(), configured_u_.end())) {
        return; // a retry after a cut starts where the last attempt did
    }
    ElementGeometry g = build_geometry(mesh, settings_.integration, u.data());
    geom_ = std::move(g);
    configured_u_.assign(u.begin(), u.end());
    ++counters_.geometry_updates;
}

template <int D>
void ContinuumAssembly::strains_ul(const Mesh& mesh, std::span<const double> du) {
    using Tr = ElementTraits<D>;
    const std::size_t ne = static_cast<std::size_t>(mesh.n_elements());
    std::vector<unsigned char>& inverted = inverted_flags_;
    inverted.assign(ne, 0);
    for_each_index(ne, settings_.element_grain, [&](std::size_t e) {
        SetData& s = *sets_[static_cast<std::size_t>(set_of_element_[e])];
        const int ei = static_cast<int>(e);
        double ue[Tr::ndof];
        for (int a = 0; a < Tr::nen; ++a) {
            const int n = mesh.node(ei, a);
            for (int i = 0; i < D; ++i) {
                ue[a * D + i] = du[static_cast<std::size_t>(n * D + i)];
            }
        }
        if (settings_.integration == Integration::reduced &&
            inverted_at_gauss_points<D>(mesh, ei, ue)) {
            inverted[e] = 1; // the one point's averaged gradient does not see an hourglass fold
        }
        for (int q = 0; q < geom_.nip; ++q) {
            const Mat3 G = increment_gradient<D>(geom_.gradients(ei, q), ue);
            const IncrementKinematics k = increment_kinematics(G);
            if (!(k.J > 0.0) || !k.R.allFinite() ||
                !std::isfinite(k.deps[0] + k.deps[1] + k.deps[2] + k.deps[3] + k.deps[4] +
                               k.deps[5])) {
                inverted[e] = 1;
            }
            const auto p = static_cast<std::size_t>(local_of_element_[e] * geom_.nip + q);
            for (int j = 0; j < 6; ++j) {
                s.deps_cols[static_cast<std::size_t>(j)][p] = k.deps[static_cast<std::size_t>(j)];
            }
            double* r = s.rotations.data() + 9 * p;
            double* g = increment_gradients_.data() +
                        9 * (e * static_cast<std::size_t>(geom_.nip) + static_cast<std::size_t>(q));
            for (int a = 0; a < 3; ++a) {
                for (int b = 0; b < 3; ++b) {
                    r[3 * a + b] = k.R(a, b);
                    g[3 * a + b] = G(a, b);
                }
            }
        }
    });
    inverted_.clear();
    for (std::size_t e = 0; e < ne; ++e) {
        if (inverted[e] != 0) {
            inverted_.push_back(static_cast<int>(e));
        }
    }
    for (auto& s : sets_) {
        s->material->rotate_start(s->rotations.data());
    }
}

template <int D>
void ContinuumAssembly::internal_force_ul(const Mesh& mesh, const SparseSystem& system,
                                          std::span<const double> u, std::span<const double> du,
                                          std::vector<double>& f_int) {
    // Hourglass base vectors of the reference: a rigid rotation is linear in X.
    force_loop<D>(mesh, system, u, du, f_int, reference_,
                  [&](int e, std::size_t set, int local, double* f) {
                      const SetData& s = *sets_[set];
                      const auto eu = static_cast<std::size_t>(e);
                      for (int q = 0; q < geom_.nip; ++q) {
                          const auto p = static_cast<std::size_t>(local * geom_.nip + q);
                          Sym<double> sigma;
                          for (int j = 0; j < 6; ++j) {
                              sigma[static_cast<std::size_t>(j)] = s.material->trial(j)[p];
                          }
                          const Mat3 G = stored_gradient(increment_gradients_, eu, q, geom_.nip);
                          const Mat3 P = first_piola(sigma, increment_kinematics(G));
                          add_piola_force<D>(geom_.gradients(e, q), P, geom_.weight(e, q), f);
                      }
                  });
}

template <int D>
void ContinuumAssembly::tangent_ul(const Mesh& mesh, SparseSystem& system,
                                   PrescribedCoupling* coupling) {
    using Tr = ElementTraits<D>;
    constexpr int nc = Tr::ncomp;
    constexpr auto comps = Tr::voigt_of();
    const bool reduced = settings_.integration == Integration::reduced;
    for (int c = 0; c < system.n_colours(); ++c) {
        const auto elements = system.colour(c);
        for_each_index(elements.size(), colour_grain(elements.size()), [&](std::size_t k) {
            const int e = elements[k];
            const auto eu = static_cast<std::size_t>(e);
            const SetData& s = *sets_[static_cast<std::size_t>(set_of_element_[eu])];
            const int local = local_of_element_[eu];
            Eigen::Matrix<double, Tr::ndof, Tr::ndof> K =
                Eigen::Matrix<double, Tr::ndof, Tr::ndof>::Zero();
            for (int q = 0; q < geom_.nip; ++q) {
                const auto p = static_cast<std::size_t>(local * geom_.nip + q);
                Sym<double> sigma, sigma_n;
                for (int j = 0; j < 6; ++j) {
                    sigma[static_cast<std::size_t>(j)] = s.material->trial(j)[p];
                    sigma_n[static_cast<std::size_t>(j)] = s.material->committed(j)[p];
                }
                const Mat3 G = stored_gradient(increment_gradients_, eu, q, geom_.nip);
                const auto A = first_piola_tangent<D>(G, sigma, sigma_n,
                                                      s.tangent.data() + p * nc * nc, comps);
                add_piola_tangent<D>(geom_.gradients(e, q), A, geom_.weight(e, q), K);
            }
            if (reduced) {
                add_hourglass_tangent<D>(reference_.hourglass_gamma.data() +
                                             eu * Tr::n_hourglass * Tr::nen,
                                         hourglass_k_[eu], K);
            }
            scatter_tangent<D>(mesh, system, coupling, e, K.data());
        });
    }
}

template void ContinuumAssembly::strains_ul<2>(const Mesh&, std::span<const double>);
template void ContinuumAssembly::strains_ul<3>(const Mesh&, std::span<const double>);
template void ContinuumAssembly::internal_force_ul<2>(const Mesh&, const SparseSystem&,
                                                      std::span<const double>,
                                                      std::span<const double>,
                                                      std::vector<double>&);
template void ContinuumAssembly::internal_force_ul<3>(const Mesh&, const SparseSystem&,
                                                      std::span<const double>,
                                                      std::span<const double>,
                                                      std::vector<double>&);
template void ContinuumAssembly::tangent_ul<2>(const Mesh&, SparseSystem&, PrescribedCoupling*);
template void ContinuumAssembly::tangent_ul<3>(const Mesh&, SparseSystem&, PrescribedCoupling*);

} // namespace ifsim::fem
