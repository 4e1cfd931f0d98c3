#include "fem/mesh.hpp"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

namespace ifsim::fem {
namespace {

// Edges of quad4: bottom, right, top, left (counter-clockwise: outward normal (t_y, -t_x)).
constexpr int quad4_faces[4][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}};
// Faces of hex8: zeta=-1, zeta=+1, eta=-1, xi=+1, eta=+1, xi=-1.
constexpr int hex8_faces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                  {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};

template <class Map>
const auto& find_set(const Map& sets, const std::string& name, const char* kind) {
    const auto it = sets.find(name);
    if (it == sets.end()) {
        throw std::out_of_range(fmt::format("the mesh has no {} set '{}'", kind, name));
    }
    return it->second;
}

} // namespace

std::span<const int> face_nodes(ElementType t, int local_face) {
    if (local_face < 0 || local_face >= faces_per_element(t)) {
        throw std::out_of_range(fmt::format("local face {} does not exist", local_face));
    }
    if (t == ElementType::quad4) {
        return {quad4_faces[local_face], 2};
    }
    return {hex8_faces[local_face], 4};
}

const std::vector<int>& Mesh::node_set(const std::string& name) const {
    return find_set(node_sets, name, "node");
}
const std::vector<FaceRef>& Mesh::face_set(const std::string& name) const {
    return find_set(face_sets, name, "face");
}
const std::vector<int>& Mesh::element_set(const std::string& name) const {
    return find_set(element_sets, name, "element");
}

std::vector<int> Mesh::nodes_of_faces(const std::string& face_set_name) const {
    std::vector<int> nodes;
    for (const FaceRef& f : face_set(face_set_name)) {
        for (int local : face_nodes(type, f.local_face)) {
            nodes.push_back(node(f.element, local));
        }
    }
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    return nodes;
}

void Mesh::validate() const {
    if (coordinates.size() % static_cast<std::size_t>(dim()) != 0) {
        throw std::invalid_argument("mesh coordinates are not a multiple of the dimension");
    }
    if (connectivity.size() % static_cast<std::size_t>(nodes_per_element()) != 0) {
        throw std::invalid_argument("mesh connectivity is not a multiple of the element size");
    }
    const int nn = n_nodes();
    const int ne = n_elements();
    for (std::size_t i = 0; i < connectivity.size(); ++i) {
        if (connectivity[i] < 0 || connectivity[i] >= nn) {
            throw std::invalid_argument(fmt::format("element {} names node {} (mesh has {})",
                                                    static_cast<int>(i) / nodes_per_element(),
                                                    connectivity[i], nn));
        }
    }
    for (const auto& [name, nodes] : node_sets) {
        for (int n : nodes) {
            if (n < 0 || n >= nn) {
                throw std::invalid_argument(fmt::format("node set '{}' names node {}", name, n));
            }
        }
    }
    for (const auto& [name, faces] : face_sets) {
        for (const FaceRef& f : faces) {
            if (f.element < 0 || f.element >= ne || f.local_face < 0 ||
                f.local_face >= faces_per_element(type)) {
                throw std::invalid_argument(fmt::format("face set '{}' names face {} of element {}",
                                                        name, f.local_face, f.element));
            }
        }
    }
    for (const auto& [name, elements] : element_sets) {
        for (int e : elements) {
            if (e < 0 || e >= ne) {
                throw std::invalid_argument(
                    fmt::format("element set '{}' names element {}", name, e));
            }
        }
    }
}

} // namespace ifsim::fem
