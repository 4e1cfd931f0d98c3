#pragma once
// The element loop of ContinuumAssembly's internal force, shared by the small-strain and the
// updated-Lagrangian passes (they differ only in the integration-point forces): colour by
// colour, so that no two elements of a colour share a node, the scatter needs no lock and
// every sum is formed in the same order for any number of threads; plus the hourglass force
// of the total displacement under reduced integration. Internal to fem's continuum files.

#include <algorithm>

#include "engine/parallel_chunks.hpp"
#include "fem/continuum_assembly.hpp"
#include "fem/element_kernels.hpp"

namespace ifsim::fem {

// point_forces(e, set, local, f) adds the integration points' forces of element e (in material
// set `set`, local index `local` there) to f (ndof values).
template <int D, class PointForces>
void ContinuumAssembly::force_loop(const Mesh& mesh, const SparseSystem& system,
                                   std::span<const double> u, std::span<const double> du,
                                   std::vector<double>& f_int, const ElementGeometry& hourglass,
                                   PointForces&& point_forces) {
    using Tr = ElementTraits<D>;
    const bool reduced = settings_.integration == Integration::reduced;
    std::fill(f_int.begin(), f_int.end(), 0.0);
    for (int c = 0; c < system.n_colours(); ++c) {
        const auto elements = system.colour(c);
        for_each_index(elements.size(), colour_grain(elements.size()), [&](std::size_t k) {
            const int e = elements[k];
            const auto eu = static_cast<std::size_t>(e);
            const auto set = static_cast<std::size_t>(set_of_element_[eu]);
            const int local = local_of_element_[eu];
            int dof[Tr::ndof];
            for (int a = 0; a < Tr::nen; ++a) {
                for (int i = 0; i < D; ++i) {
                    dof[a * D + i] = mesh.node(e, a) * D + i;
                }
            }
            double f[Tr::ndof] = {};
            point_forces(e, set, local, f);
            if (reduced) { // hourglass force of the total displacement
                double ut[Tr::ndof];
                for (int k2 = 0; k2 < Tr::ndof; ++k2) {
                    const auto d = static_cast<std::size_t>(dof[k2]);
                    ut[k2] = u[d] + du[d];
                }
                add_hourglass_force<D>(hourglass.hourglass_gamma.data() +
                                           eu * Tr::n_hourglass * Tr::nen,
                                       hourglass_k_[eu], ut, f);
            }
            for (int k2 = 0; k2 < Tr::ndof; ++k2) {
                f_int[static_cast<std::size_t>(dof[k2])] += f[k2];
            }
        });
    }
}

} // namespace ifsim::fem
