#include "io/mesh/gmsh_reader.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <map>
#include <numeric>
#include <unordered_map>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "io/element_test/element_orientation.hpp"
#include "io/mesh/gmsh_error.hpp"
#include "io/mesh/gmsh_parse.hpp"

namespace ifsim::io {

namespace {

// Sorted node indices of a face; a 2D edge fills the last two entries with `unused`.
using FaceKey = std::array<int, 4>;
constexpr int unused = std::numeric_limits<int>::max();

struct FaceEntry {
    fem::FaceRef face;
    int count = 0;
};

int dimension_of(const GmshElement& e) {
    return gmsh_element_type(e.type)->dimension;
}

const char* type_name(int type) {
    return gmsh_element_type(type)->name;
}

// Builds the mesh step by step; each step throws MeshFileError for what it checks.
class Builder {
public:
    explicit Builder(const GmshContent& c) : c_(c) {}

    GmshMesh build() {
        find_dimension();
        index_nodes();
        collect_volumes();
        number_nodes();
        connect_and_orient();
        volume_sets();
        lower_sets();
        finish_sets();
        return std::move(out_);
    }

private:
    [[noreturn]] void fail(int line, const std::string& message) const {
        throw MeshFileError(c_.file, line, message);
    }

    void find_dimension() {
        for (const GmshElement& e : c_.elements) {
            dim_ = std::max(dim_, dimension_of(e));
        }
        if (dim_ < 2) {
            fail(0, "expected a 2D mesh of 4-node quadrangles or a 3D mesh of 8-node hexahedra, "
                    "the file has no elements of dimension 2 or 3");
        }
        out_.mesh.type = dim_ == 2 ? fem::ElementType::quad4 : fem::ElementType::hex8;
        volume_type_ = dim_ == 2 ? 3 : 5;
        face_type_ = dim_ == 2 ? 1 : 3;
    }

    void index_nodes() {
        node_at_.reserve(c_.nodes.size());
        for (std::size_t i = 0; i < c_.nodes.size(); ++i) {
            const auto [it, added] = node_at_.try_emplace(c_.nodes[i].tag, i);
            if (!added) {
                fail(c_.nodes[i].line,
                     fmt::format("node tag {} is defined twice (first on line {})", c_.nodes[i].tag,
                                 c_.nodes[it->second].line));
            }
        }
    }

    void collect_volumes() {
        for (const GmshElement& e : c_.elements) {
            if (dimension_of(e) != dim_) {
                continue;
            }
            if (e.type != volume_type_) {
                fail(e.line, fmt::format("element {} is a {} (Gmsh type {}); a {}D mesh must "
                                         "consist of {} (type {}) only",
                                         e.tag, type_name(e.type), e.type, dim_,
                                         dim_ == 2 ? "4-node quadrangles" : "8-node hexahedra",
                                         volume_type_));
            }
            volumes_.push_back(&e);
        }
    }

    // The file's index of a node tag an element names.
    std::size_t node_index(const GmshElement& e, long long tag) const {
        const auto it = node_at_.find(tag);
        if (it == node_at_.end()) {
            fail(e.line,
                 fmt::format("element {} names node {}, which $Nodes does not define", e.tag, tag));
        }
        return it->second;
    }

    // The nodes of the volume elements, numbered densely in the order of their tags.
    void number_nodes() {
        dense_.assign(c_.nodes.size(), -1);
        for (const GmshElement* e : volumes_) {
            for (long long tag : e->nodes) {
                dense_[node_index(*e, tag)] = 0;
            }
        }
        std::vector<std::size_t> order(c_.nodes.size());
        std::iota(order.begin(), order.end(), std::size_t{0});
        std::sort(order.begin(), order.end(),
                  [&](std::size_t a, std::size_t b) { return c_.nodes[a].tag < c_.nodes[b].tag; });
        int next = 0;
        auto& x = out_.mesh.coordinates;
        for (std::size_t i : order) {
            if (dense_[i] < 0) {
                continue;
            }
            const GmshNode& n = c_.nodes[i];
            dense_[i] = next++;
            x.insert(x.end(), n.x.begin(), n.x.begin() + dim_);
            if (dim_ == 2 && n.x[2] != 0.0) {
                fail(n.line, fmt::format("node {} has z = {}; a 2D mesh must lie in the plane "
                                         "z = 0 (x, y are its coordinates)",
                                         n.tag, n.x[2]));
            }
        }
    }

    void connect_and_orient() {
        auto& conn = out_.mesh.connectivity;
        const int nen = out_.mesh.nodes_per_element();
        conn.reserve(volumes_.size() * static_cast<std::size_t>(nen));
        for (const GmshElement* e : volumes_) {
            const std::size_t first = conn.size();
            for (long long tag : e->nodes) {
                conn.push_back(dense_[node_index(*e, tag)]);
            }
            const std::span<int> nodes(conn.data() + first, static_cast<std::size_t>(nen));
            switch (orient_element(out_.mesh.type, nodes, out_.mesh.coordinates)) {
            case Orientation::kept:
                break;
            case Orientation::mirrored:
                ++out_.mirrored;
                break;
            case Orientation::invalid:
                fail(e->line, fmt::format("element {} ({}) is degenerate or too distorted: its "
                                          "Jacobian is not positive everywhere in either node "
                                          "order (expected a convex {} with distinct nodes)",
                                          e->tag, type_name(e->type),
                                          dim_ == 2 ? "quadrangle" : "hexahedron"));
            }
        }
    }

    // The set name of physical group (dim, tag); checks it is unique.
    const std::string& group(int dim, int tag, int element_line) {
        const auto key = std::make_pair(dim, tag);
        if (const auto it = group_names_.find(key); it != group_names_.end()) {
            return it->second;
        }
        const auto named = c_.names.find(key);
        const std::string name =
            named != c_.names.end() ? named->second.name : fmt::format("group{}", tag);
        const int line = named != c_.names.end() ? named->second.line : element_line;
        if (name == "all") {
            fail(line, "the physical group name \"all\" is reserved for the whole mesh (node and "
                       "element set \"all\"); expected another name");
        }
        for (const auto& [other, other_name] : group_names_) {
            if (other_name == name) {
                fail(line, fmt::format("the physical groups of dimension {} tag {} and of "
                                       "dimension {} tag {} are both named \"{}\"; expected "
                                       "unique names (they name the mesh's sets)",
                                       other.first, other.second, dim, tag, name));
            }
        }
        return group_names_.emplace(key, name).first->second;
    }

    void volume_sets() {
        const int nen = out_.mesh.nodes_per_element();
        for (std::size_t k = 0; k < volumes_.size(); ++k) {
            for (int g : volumes_[k]->physicals) {
                const std::string& name = group(dim_, g, volumes_[k]->line);
                out_.mesh.element_sets[name].push_back(static_cast<int>(k));
                auto& nodes = out_.mesh.node_sets[name];
                for (int a = 0; a < nen; ++a) {
                    nodes.push_back(out_.mesh.node(static_cast<int>(k), a));
                }
            }
        }
    }

    void index_faces() {
        const fem::Mesh& m = out_.mesh;
        for (int e = 0; e < m.n_elements(); ++e) {
            for (int f = 0; f < fem::faces_per_element(m.type); ++f) {
                FaceKey key{unused, unused, unused, unused};
                int i = 0;
                for (int local : fem::face_nodes(m.type, f)) {
                    key[static_cast<std::size_t>(i++)] = m.node(e, local);
                }
                std::sort(key.begin(), key.end());
                FaceEntry& entry = faces_[key];
                entry.face = {e, f};
                ++entry.count;
            }
        }
    }

    // The mesh node of a lower-dimensional element's node tag.
    int mesh_node(const GmshElement& e, long long tag, const std::string& name) const {
        const int n = dense_[node_index(e, tag)];
        if (n < 0) {
            fail(e.line,
                 fmt::format("element {} of physical group \"{}\" has node {}, which belongs to "
                             "no {}; expected the group on the mesh",
                             e.tag, name, tag, dim_ == 2 ? "quadrangle" : "hexahedron"));
        }
        return n;
    }

    void add_face(const GmshElement& e, const std::string& name) {
        if (e.type != face_type_) {
            fail(e.line,
                 fmt::format("element {} of boundary group \"{}\" is a {} (Gmsh type "
                             "{}); boundary groups of a {}D mesh must consist of {} "
                             "(type {}) only",
                             e.tag, name, type_name(e.type), e.type, dim_,
                             dim_ == 2 ? "2-node lines" : "4-node quadrangles", face_type_));
        }
        if (faces_.empty()) {
            index_faces();
        }
        FaceKey key{unused, unused, unused, unused};
        std::size_t i = 0;
        for (long long tag : e.nodes) {
            key[i++] = mesh_node(e, tag, name);
        }
        std::sort(key.begin(), key.end());
        const auto it = faces_.find(key);
        const char* parent = dim_ == 2 ? "quadrangle" : "hexahedron";
        if (it == faces_.end()) {
            fail(e.line, fmt::format("boundary element {} of physical group \"{}\" (nodes {}) is "
                                     "not a face of any {}; expected each boundary element to "
                                     "match a face of one {}",
                                     e.tag, name, fmt::join(e.nodes, " "), parent, parent));
        }
        if (it->second.count > 1) {
            fail(e.line,
                 fmt::format("boundary element {} of physical group \"{}\" (nodes {}) "
                             "is shared by {} elements; expected a face set on the mesh "
                             "boundary (a face of one {})",
                             e.tag, name, fmt::join(e.nodes, " "), it->second.count, parent));
        }
        out_.mesh.face_sets[name].push_back(it->second.face);
        auto& nodes = out_.mesh.node_sets[name];
        nodes.insert(nodes.end(), key.begin(), key.begin() + static_cast<std::ptrdiff_t>(i));
    }

    void lower_sets() {
        for (const GmshElement& e : c_.elements) {
            const int d = dimension_of(e);
            if (d == dim_) {
                continue;
            }
            for (int g : e.physicals) {
                const std::string& name = group(d, g, e.line);
                if (d == dim_ - 1) {
                    add_face(e, name);
                    continue;
                }
                auto& nodes = out_.mesh.node_sets[name];
                for (long long tag : e.nodes) {
                    nodes.push_back(mesh_node(e, tag, name));
                }
            }
        }
    }

    void finish_sets() {
        fem::Mesh& m = out_.mesh;
        for (auto& [name, nodes] : m.node_sets) {
            std::sort(nodes.begin(), nodes.end());
            nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
        }
        m.node_sets["all"].resize(static_cast<std::size_t>(m.n_nodes()));
        std::iota(m.node_sets["all"].begin(), m.node_sets["all"].end(), 0);
        m.element_sets["all"].resize(static_cast<std::size_t>(m.n_elements()));
        std::iota(m.element_sets["all"].begin(), m.element_sets["all"].end(), 0);
        m.validate();
    }

    const GmshContent& c_;
    GmshMesh out_;
    int dim_ = 0;
    int volume_type_ = 0;
    int face_type_ = 0;
    std::unordered_map<long long, std::size_t> node_at_; // tag -> index in c_.nodes
    std::vector<int> dense_;                             // index in c_.nodes -> mesh node
    std::vector<const GmshElement*> volumes_;
    std::map<FaceKey, FaceEntry> faces_;
    std::map<std::pair<int, int>, std::string> group_names_;
};

} // namespace

GmshMesh build_gmsh_mesh(const GmshContent& content) {
    GmshMesh out = Builder(content).build();
    out.version = content.version;
    return out;
}

GmshMesh read_gmsh_mesh(const std::string& path) {
    return build_gmsh_mesh(parse_gmsh_file(path));
}

} // namespace ifsim::io
