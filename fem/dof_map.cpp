#include "fem/dof_map.hpp"

#include <stdexcept>
#include <string>

#include <fmt/format.h>

namespace ifsim::fem {
namespace {

void check_direction(const Mesh& mesh, int direction, const std::string& set) {
    if (direction < 0 || direction >= mesh.dim()) {
        throw std::invalid_argument(fmt::format(
            "direction {} on node set '{}' does not exist in {}D", direction, set, mesh.dim()));
    }
}

} // namespace

DofMap build_dof_map(const Mesh& mesh, const Stage& stage) {
    const int D = mesh.dim();
    const auto n_dofs = static_cast<std::size_t>(mesh.n_nodes() * D);
    DofMap m;
    m.dim = D;
    m.equation.assign(n_dofs, 0);
    m.master_of.resize(n_dofs);
    for (std::size_t d = 0; d < n_dofs; ++d) {
        m.master_of[d] = static_cast<int>(d);
    }

    // Prescribed DOFs: which set prescribed them first, and the change.
    std::vector<const PrescribedDisplacement*> by(n_dofs, nullptr);
    for (const PrescribedDisplacement& p : stage.displacements) {
        check_direction(mesh, p.direction, p.node_set);
        for (int node : mesh.node_set(p.node_set)) {
            const auto d = static_cast<std::size_t>(node * D + p.direction);
            if (by[d] && by[d]->change != p.change) {
                throw std::invalid_argument(fmt::format(
                    "node {} direction {} is prescribed by node sets '{}' and '{}' with "
                    "different changes ({} and {})",
                    node, p.direction, by[d]->node_set, p.node_set, by[d]->change, p.change));
            }
            by[d] = &p;
        }
    }
    std::vector<const EqualDisplacement*> tied(n_dofs, nullptr);
    for (const EqualDisplacement& t : stage.equal_displacements) {
        check_direction(mesh, t.direction, t.node_set);
        const auto& nodes = mesh.node_set(t.node_set);
        if (nodes.empty()) {
            continue;
        }
        const int master = nodes.front() * D + t.direction;
        for (int node : nodes) {
            const auto d = static_cast<std::size_t>(node * D + t.direction);
            if (by[d]) {
                throw std::invalid_argument(fmt::format(
                    "node {} direction {} is prescribed by node set '{}' and tied by the "
                    "equal-displacement set '{}'",
                    node, t.direction, by[d]->node_set, t.node_set));
            }
            if (tied[d]) {
                throw std::invalid_argument(fmt::format(
                    "node {} direction {} is in two equal-displacement sets ('{}' and '{}')", node,
                    t.direction, tied[d]->node_set, t.node_set));
            }
            tied[d] = &t;
            m.master_of[d] = master;
        }
    }

    int next = 0;
    for (std::size_t d = 0; d < n_dofs; ++d) {
        if (by[d]) {
            m.equation[d] = -1;
            m.prescribed.push_back(static_cast<int>(d));
            m.prescribed_change.push_back(by[d]->change);
        } else if (m.master_of[d] == static_cast<int>(d)) {
            m.equation[d] = next++;
        }
    }
    for (std::size_t d = 0; d < n_dofs; ++d) { // slaves after their masters are numbered
        if (!by[d] && m.master_of[d] != static_cast<int>(d)) {
            m.equation[d] = m.equation[static_cast<std::size_t>(m.master_of[d])];
        }
    }
    m.n_equations = next;
    return m;
}

} // namespace ifsim::fem
