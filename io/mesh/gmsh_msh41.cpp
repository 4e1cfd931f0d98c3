#include "io/mesh/gmsh_msh41.hpp"

#include <limits>

#include <fmt/format.h>

#include "io/mesh/gmsh_parse.hpp"

namespace ifsim::io {

namespace {

constexpr long long max_count = std::numeric_limits<int>::max();
constexpr long long max_tag = std::numeric_limits<long long>::max();

} // namespace

bool Msh41Reader::read_section(std::string_view header, GmshCursor& c, GmshContent& out) {
    if (header == "$Entities") {
        read_entities(c);
    } else if (header == "$Nodes") {
        read_nodes(c, out);
    } else if (header == "$Elements") {
        read_elements(c, out);
    } else {
        return false;
    }
    return true;
}

// numPoints numCurves numSurfaces numVolumes, then per entity its tag, its position (points:
// x y z) or bounding box (6 numbers), its physical tags and (not points) its bounding
// entities.
void Msh41Reader::read_entities(GmshCursor& c) {
    long long counts[4];
    for (auto& n : counts) {
        n = c.integer("the number of entities of a dimension", 0, max_count);
    }
    for (int dim = 0; dim < 4; ++dim) {
        for (long long i = 0; i < counts[dim]; ++i) {
            const int tag = static_cast<int>(c.integer("an entity tag", 1, max_count));
            for (int k = 0; k < (dim == 0 ? 3 : 6); ++k) {
                c.skip_real(dim == 0 ? "a point coordinate" : "a bounding box coordinate");
            }
            std::vector<int>& groups = physicals_[{dim, tag}];
            const long long n = c.integer("the number of physical tags", 0, max_count);
            for (long long k = 0; k < n; ++k) {
                groups.push_back(
                    static_cast<int>(c.integer("a physical tag", -max_count, max_count)));
            }
            if (dim > 0) {
                const long long nb = c.integer("the number of bounding entities", 0, max_count);
                for (long long k = 0; k < nb; ++k) {
                    c.integer("a bounding entity tag", -max_count, max_count);
                }
            }
        }
    }
    entities_read_ = true;
    c.expect_end();
}

// numEntityBlocks numNodes minNodeTag maxNodeTag; per block: entityDim entityTag parametric
// numNodesInBlock, the block's node tags, then their coordinates x y z (and entityDim
// parametric coordinates when parametric is 1).
void Msh41Reader::read_nodes(GmshCursor& c, GmshContent& out) {
    const int header = c.line();
    const long long blocks = c.integer("the number of node blocks", 0, max_count);
    const long long total = c.integer("the number of nodes", 0, max_count);
    c.integer("the smallest node tag", 0, max_tag);
    c.integer("the largest node tag", 0, max_tag);
    long long read = 0;
    for (long long b = 0; b < blocks; ++b) {
        const int dim = static_cast<int>(c.integer("a node block's entity dimension", 0, 3));
        c.integer("a node block's entity tag", 1, max_count);
        const bool parametric = c.integer("a node block's parametric flag", 0, 1) == 1;
        const long long n = c.integer("the number of nodes in the block", 0, total - read);
        const std::size_t first = out.nodes.size();
        for (long long k = 0; k < n; ++k) {
            GmshNode node;
            node.tag = c.integer("a node tag", 1, max_tag);
            out.nodes.push_back(node);
        }
        for (long long k = 0; k < n; ++k) {
            GmshNode& node = out.nodes[first + static_cast<std::size_t>(k)];
            for (double& x : node.x) {
                x = c.real("a node coordinate");
            }
            node.line = c.line();
            for (int p = 0; parametric && p < dim; ++p) {
                c.real("a parametric node coordinate");
            }
        }
        read += n;
    }
    if (read != total) {
        c.fail_at(header, fmt::format("the $Nodes section announces {} nodes, its blocks hold {}",
                                      total, read));
    }
    c.expect_end();
}

// numEntityBlocks numElements minElementTag maxElementTag; per block: entityDim entityTag
// elementType numElementsInBlock, then per element its tag and node tags.
void Msh41Reader::read_elements(GmshCursor& c, GmshContent& out) {
    const int header = c.line();
    const long long blocks = c.integer("the number of element blocks", 0, max_count);
    const long long total = c.integer("the number of elements", 0, max_count);
    c.integer("the smallest element tag", 0, max_tag);
    c.integer("the largest element tag", 0, max_tag);
    long long read = 0;
    for (long long b = 0; b < blocks; ++b) {
        Block block;
        block.dim = static_cast<int>(c.integer("an element block's entity dimension", 0, 3));
        block.line = c.line();
        block.tag = static_cast<int>(c.integer("an element block's entity tag", 1, max_count));
        const int type = static_cast<int>(c.integer("an element type", 1, max_count));
        const GmshElementType* info = gmsh_element_type(type);
        if (info != nullptr && info->dimension != block.dim) {
            c.fail(fmt::format("element type {} ({}) has dimension {}, but the block's entity "
                               "has dimension {}",
                               type, info->name, info->dimension, block.dim));
        }
        const long long n = c.integer("the number of elements in the block", 0, total - read);
        block.first = out.elements.size();
        for (long long k = 0; k < n; ++k) {
            GmshElement e;
            e.tag = c.integer("an element tag", 1, max_tag);
            read_element_nodes(c, type, c.line(), e);
            out.elements.push_back(std::move(e));
        }
        block.end = out.elements.size();
        blocks_.push_back(block);
        read += n;
    }
    if (read != total) {
        c.fail_at(header,
                  fmt::format("the $Elements section announces {} elements, its blocks hold {}",
                              total, read));
    }
    c.expect_end();
}

void Msh41Reader::finish(const GmshCursor& c, GmshContent& out) const {
    for (const Block& b : blocks_) {
        const auto it = physicals_.find({b.dim, b.tag});
        if (it == physicals_.end()) {
            if (entities_read_) {
                c.fail_at(b.line, fmt::format("the element block of entity {} (dimension {}) "
                                              "names an entity that $Entities does not list",
                                              b.tag, b.dim));
            }
            continue; // no $Entities: no physical groups
        }
        for (std::size_t e = b.first; e < b.end; ++e) {
            out.elements[e].physicals = it->second;
        }
    }
}

} // namespace ifsim::io
