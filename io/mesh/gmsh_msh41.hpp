#pragma once
// The sections of MSH 4.1 that carry the mesh: $Entities (the physical groups of each
// geometric entity), $Nodes and $Elements (in blocks per entity). An element's physical
// groups are its entity's; they are resolved in finish(), once every section was read.

#include <map>
#include <string_view>
#include <utility>
#include <vector>

#include "io/mesh/gmsh_content.hpp"
#include "io/mesh/gmsh_cursor.hpp"

namespace ifsim::io {

class Msh41Reader {
public:
    // Reads the section whose header was just read; false for a section it does not know.
    bool read_section(std::string_view header, GmshCursor& c, GmshContent& out);
    // Gives each element the physical groups of its entity. Throws MeshFileError for an
    // element block of an entity that $Entities does not list.
    void finish(const GmshCursor& c, GmshContent& out) const;

private:
    struct Block {
        int dim = 0;
        int tag = 0;
        int line = 0;
        std::size_t first = 0; // elements [first, end) of GmshContent::elements
        std::size_t end = 0;
    };
    void read_entities(GmshCursor& c);
    void read_nodes(GmshCursor& c, GmshContent& out);
    void read_elements(GmshCursor& c, GmshContent& out);

    bool entities_read_ = false;
    std::map<std::pair<int, int>, std::vector<int>> physicals_; // (dim, entity tag) -> groups
    std::vector<Block> blocks_;
};

} // namespace ifsim::io
