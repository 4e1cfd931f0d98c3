#pragma once
// A finite-element mesh of one element type (quad4 in 2D plane strain, hex8 in 3D) with named
// node, face and element sets. Coordinates and connectivity are flat arrays (node-major
// coordinates x0 y0 [z0] x1 ..., element-major connectivity), the layout the element loops
// read directly.
//
// Local node order (natural coordinates):
//   quad4: 0 (-1,-1), 1 (1,-1), 2 (1,1), 3 (-1,1)            counter-clockwise
//   hex8:  0..3 as quad4 at zeta = -1, 4..7 the same at zeta = +1
// Local faces are listed by face_nodes() with their nodes ordered so that the right-hand rule
// gives the outward normal.

#include <array>
#include <map>
#include <span>
#include <string>
#include <vector>

namespace ifsim::fem {

enum class ElementType { quad4, hex8 };

inline constexpr int dimension(ElementType t) {
    return t == ElementType::quad4 ? 2 : 3;
}
inline constexpr int nodes_per_element(ElementType t) {
    return t == ElementType::quad4 ? 4 : 8;
}
inline constexpr int faces_per_element(ElementType t) {
    return t == ElementType::quad4 ? 4 : 6;
}
inline constexpr int nodes_per_face(ElementType t) {
    return t == ElementType::quad4 ? 2 : 4;
}

// Local node indices of a local face (edge for quad4), outward-normal ordering.
std::span<const int> face_nodes(ElementType t, int local_face);

struct FaceRef {
    int element = 0;
    int local_face = 0;
    bool operator==(const FaceRef&) const = default;
};

struct Mesh {
    ElementType type = ElementType::quad4;
    std::vector<double> coordinates; // dim per node
    std::vector<int> connectivity;   // nodes_per_element per element
    std::map<std::string, std::vector<int>> node_sets;
    std::map<std::string, std::vector<FaceRef>> face_sets;
    std::map<std::string, std::vector<int>> element_sets;

    int dim() const { return dimension(type); }
    int nodes_per_element() const { return fem::nodes_per_element(type); }
    int n_nodes() const { return static_cast<int>(coordinates.size()) / dim(); }
    int n_elements() const { return static_cast<int>(connectivity.size()) / nodes_per_element(); }
    int node(int element, int local) const {
        return connectivity[static_cast<std::size_t>(element * nodes_per_element() + local)];
    }
    double coordinate(int node, int axis) const {
        return coordinates[static_cast<std::size_t>(node * dim() + axis)];
    }

    // Named sets; throw std::out_of_range naming the set when it does not exist.
    const std::vector<int>& node_set(const std::string& name) const;
    const std::vector<FaceRef>& face_set(const std::string& name) const;
    const std::vector<int>& element_set(const std::string& name) const;

    // Sorted, unique nodes of a face set.
    std::vector<int> nodes_of_faces(const std::string& face_set_name) const;

    // Throws std::invalid_argument when a node index, set member or coordinate array is
    // inconsistent; called by the solver before it builds anything on the mesh.
    void validate() const;
};

} // namespace ifsim::fem
