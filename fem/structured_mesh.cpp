#include "fem/structured_mesh.hpp"

#include <numeric>
#include <stdexcept>

namespace ifsim::fem {

Mesh rectangle_mesh(const RectangleSpec& s) {
    if (s.nx < 1 || s.ny < 1 || !(s.width > 0.0) || !(s.height > 0.0)) {
        throw std::invalid_argument("rectangle mesh needs positive sizes and element counts");
    }
    Mesh m;
    m.type = ElementType::quad4;
    const auto id = [&](int i, int j) { return i + (s.nx + 1) * j; };
    for (int j = 0; j <= s.ny; ++j) {
        for (int i = 0; i <= s.nx; ++i) {
            m.coordinates.push_back(s.origin[0] + s.width * i / s.nx);
            m.coordinates.push_back(s.origin[1] + s.height * j / s.ny);
        }
    }
    for (int j = 0; j < s.ny; ++j) {
        for (int i = 0; i < s.nx; ++i) {
            m.connectivity.insert(m.connectivity.end(),
                                  {id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
        }
    }
    const auto elem = [&](int i, int j) { return i + s.nx * j; };
    auto& ns = m.node_sets;
    auto& fs = m.face_sets;
    for (int j = 0; j <= s.ny; ++j) {
        ns["left"].push_back(id(0, j));
        ns["right"].push_back(id(s.nx, j));
    }
    for (int i = 0; i <= s.nx; ++i) {
        ns["bottom"].push_back(id(i, 0));
        ns["top"].push_back(id(i, s.ny));
    }
    for (int j = 0; j < s.ny; ++j) {
        fs["left"].push_back({elem(0, j), 3});
        fs["right"].push_back({elem(s.nx - 1, j), 1});
    }
    for (int i = 0; i < s.nx; ++i) {
        fs["bottom"].push_back({elem(i, 0), 0});
        fs["top"].push_back({elem(i, s.ny - 1), 2});
    }
    ns["all"].resize(static_cast<std::size_t>(m.n_nodes()));
    std::iota(ns["all"].begin(), ns["all"].end(), 0);
    m.element_sets["all"].resize(static_cast<std::size_t>(m.n_elements()));
    std::iota(m.element_sets["all"].begin(), m.element_sets["all"].end(), 0);
    return m;
}

Mesh box_mesh(const BoxSpec& s) {
    if (s.nx < 1 || s.ny < 1 || s.nz < 1 || !(s.width > 0.0) || !(s.depth > 0.0) ||
        !(s.height > 0.0)) {
        throw std::invalid_argument("box mesh needs positive sizes and element counts");
    }
    Mesh m;
    m.type = ElementType::hex8;
    const auto id = [&](int i, int j, int k) { return i + (s.nx + 1) * (j + (s.ny + 1) * k); };
    for (int k = 0; k <= s.nz; ++k) {
        for (int j = 0; j <= s.ny; ++j) {
            for (int i = 0; i <= s.nx; ++i) {
                m.coordinates.push_back(s.origin[0] + s.width * i / s.nx);
                m.coordinates.push_back(s.origin[1] + s.depth * j / s.ny);
                m.coordinates.push_back(s.origin[2] + s.height * k / s.nz);
            }
        }
    }
    for (int k = 0; k < s.nz; ++k) {
        for (int j = 0; j < s.ny; ++j) {
            for (int i = 0; i < s.nx; ++i) {
                m.connectivity.insert(m.connectivity.end(),
                                      {id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k),
                                       id(i, j + 1, k), id(i, j, k + 1), id(i + 1, j, k + 1),
                                       id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)});
            }
        }
    }
    const auto elem = [&](int i, int j, int k) { return i + s.nx * (j + s.ny * k); };
    auto& ns = m.node_sets;
    auto& fs = m.face_sets;
    for (int k = 0; k <= s.nz; ++k) {
        for (int j = 0; j <= s.ny; ++j) {
            for (int i = 0; i <= s.nx; ++i) {
                const int n = id(i, j, k);
                if (i == 0) {
                    ns["left"].push_back(n);
                }
                if (i == s.nx) {
                    ns["right"].push_back(n);
                }
                if (j == 0) {
                    ns["front"].push_back(n);
                }
                if (j == s.ny) {
                    ns["back"].push_back(n);
                }
                if (k == 0) {
                    ns["bottom"].push_back(n);
                }
                if (k == s.nz) {
                    ns["top"].push_back(n);
                }
            }
        }
    }
    for (int k = 0; k < s.nz; ++k) {
        for (int j = 0; j < s.ny; ++j) {
            for (int i = 0; i < s.nx; ++i) {
                const int e = elem(i, j, k);
                if (k == 0) {
                    fs["bottom"].push_back({e, 0});
                }
                if (k == s.nz - 1) {
                    fs["top"].push_back({e, 1});
                }
                if (j == 0) {
                    fs["front"].push_back({e, 2});
                }
                if (i == s.nx - 1) {
                    fs["right"].push_back({e, 3});
                }
                if (j == s.ny - 1) {
                    fs["back"].push_back({e, 4});
                }
                if (i == 0) {
                    fs["left"].push_back({e, 5});
                }
            }
        }
    }
    ns["all"].resize(static_cast<std::size_t>(m.n_nodes()));
    std::iota(ns["all"].begin(), ns["all"].end(), 0);
    m.element_sets["all"].resize(static_cast<std::size_t>(m.n_elements()));
    std::iota(m.element_sets["all"].begin(), m.element_sets["all"].end(), 0);
    return m;
}

void append_body(Mesh& into, const Mesh& body, const std::string& name) {
    if (into.n_elements() > 0 && into.type != body.type) {
        throw std::invalid_argument("body '" + name + "' has another element type than the mesh");
    }
    if (into.element_sets.contains(name)) {
        throw std::invalid_argument("a body named '" + name + "' exists already");
    }
    into.type = body.type;
    const int node0 = into.n_nodes();
    const int elem0 = into.n_elements();
    into.coordinates.insert(into.coordinates.end(), body.coordinates.begin(),
                            body.coordinates.end());
    for (int n : body.connectivity) {
        into.connectivity.push_back(node0 + n);
    }
    for (const auto& [set, nodes] : body.node_sets) {
        auto& out = into.node_sets[name + "." + set];
        for (int n : nodes) {
            out.push_back(node0 + n);
        }
    }
    for (const auto& [set, faces] : body.face_sets) {
        auto& out = into.face_sets[name + "." + set];
        for (const FaceRef& f : faces) {
            out.push_back({elem0 + f.element, f.local_face});
        }
    }
    for (const auto& [set, elements] : body.element_sets) {
        auto& out = into.element_sets[set == "all" ? name : name + "." + set];
        for (int e : elements) {
            out.push_back(elem0 + e);
        }
    }
}

} // namespace ifsim::fem
