#include "io/mesh/gmsh_msh22.hpp"

#include <algorithm>
#include <limits>
#include <map>
#include <utility>

#include "io/mesh/gmsh_parse.hpp"

namespace ifsim::io {

namespace {

constexpr long long max_count = std::numeric_limits<int>::max();
constexpr long long max_tag = std::numeric_limits<long long>::max();

void read_nodes(GmshCursor& c, GmshContent& out) {
    const long long n = c.integer("the number of nodes", 0, max_count);
    for (long long k = 0; k < n; ++k) {
        GmshNode node;
        node.tag = c.integer("a node tag", 1, max_tag);
        node.line = c.line();
        for (double& x : node.x) {
            x = c.real("a node coordinate");
        }
        out.nodes.push_back(node);
    }
    c.expect_end();
}

void read_elements(GmshCursor& c, GmshContent& out) {
    const long long n = c.integer("the number of elements", 0, max_count);
    for (long long k = 0; k < n; ++k) {
        GmshElement e;
        e.tag = c.integer("an element tag", 1, max_tag);
        const int line = c.line();
        const int type = static_cast<int>(c.integer("an element type", 1, max_count));
        const long long tags = c.integer("the number of element tags", 0, 1000);
        for (long long t = 0; t < tags; ++t) {
            const long long v = c.integer("an element tag value", -max_count, max_count);
            if (t == 0 && v != 0) {
                e.physicals.push_back(static_cast<int>(v));
            }
        }
        read_element_nodes(c, type, line, e);
        out.elements.push_back(std::move(e));
    }
    c.expect_end();
}

} // namespace

bool Msh22Reader::read_section(std::string_view header, GmshCursor& c, GmshContent& out) {
    if (header == "$Nodes") {
        read_nodes(c, out);
    } else if (header == "$Elements") {
        read_elements(c, out);
    } else {
        return false;
    }
    return true;
}

void Msh22Reader::finish(GmshContent& out) const {
    std::map<std::pair<int, std::vector<long long>>, std::size_t> first;
    std::vector<GmshElement> merged;
    merged.reserve(out.elements.size());
    for (GmshElement& e : out.elements) {
        std::vector<long long> key = e.nodes;
        std::sort(key.begin(), key.end());
        const auto [it, added] = first.try_emplace({e.type, std::move(key)}, merged.size());
        if (added) {
            merged.push_back(std::move(e));
            continue;
        }
        auto& groups = merged[it->second].physicals;
        for (int g : e.physicals) {
            if (std::find(groups.begin(), groups.end(), g) == groups.end()) {
                groups.push_back(g);
            }
        }
    }
    out.elements = std::move(merged);
}

} // namespace ifsim::io
