#pragma once
// The sections of MSH 2.2 that carry the mesh: $Nodes ("tag x y z" per node) and $Elements
// ("tag type number-of-tags tags... nodes..." per element; the first tag is the physical
// group, 0 for none). An element in several physical groups is written once per group; those
// copies are merged into one element with all their groups in finish().

#include <string_view>

#include "io/mesh/gmsh_content.hpp"
#include "io/mesh/gmsh_cursor.hpp"

namespace ifsim::io {

class Msh22Reader {
public:
    // Reads the section whose header was just read; false for a section it does not know.
    bool read_section(std::string_view header, GmshCursor& c, GmshContent& out);
    // Merges the copies of an element (same type and nodes) into its first one.
    void finish(GmshContent& out) const;
};

} // namespace ifsim::io
