#pragma once
// What a Gmsh mesh file holds, before it becomes an fem::Mesh: nodes by tag, every element
// with its Gmsh type, node tags and physical groups, the physical groups' names, each with the
// file line it came from for messages. Filled by the MSH 4.1 and 2.2 parsers.

#include <array>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace ifsim::io {

struct GmshNode {
    long long tag = 0;
    std::array<double, 3> x{};
    int line = 0;
};

struct GmshElement {
    long long tag = 0;
    int type = 0; // Gmsh element type number
    std::vector<long long> nodes;
    std::vector<int> physicals; // physical group tags (of the element's dimension)
    int line = 0;
};

struct GmshName {
    std::string name;
    int line = 0;
};

struct GmshContent {
    std::string file;
    std::string version; // "4.1" | "2.2"
    std::vector<GmshNode> nodes;
    std::vector<GmshElement> elements;
    std::map<std::pair<int, int>, GmshName> names; // (dimension, physical tag) -> name
};

// A Gmsh element type: its dimension, node count and name.
struct GmshElementType {
    int dimension = 0;
    int nodes = 0;
    const char* name = "";
};

// The element types of Gmsh's linear and quadratic families; nullptr for another number.
const GmshElementType* gmsh_element_type(int type);

} // namespace ifsim::io
