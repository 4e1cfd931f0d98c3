#pragma once
// Parsing a Gmsh mesh file, MSH 4.1 or 2.2 (ASCII, or binary through its ASCII form,
// gmsh_binary.hpp), into GmshContent: $MeshFormat first, then
// $PhysicalNames, $Entities (4.1), $Nodes and $Elements; other sections ($Comments,
// $NodeData, $Periodic, ...) are skipped. Throws MeshFileError naming the file and the line
// (missing or unreadable file, another version, truncated section, bad number,
// unknown element type).

#include <string>

#include "io/mesh/gmsh_content.hpp"
#include "io/mesh/gmsh_cursor.hpp"

namespace ifsim::io {

GmshContent parse_gmsh_file(const std::string& path);

// The same for the file's text (`file` names it in messages).
GmshContent parse_gmsh_text(std::string text, const std::string& file);

// A file's bytes, ASCII or binary (`file` names it in messages).
GmshContent parse_gmsh_bytes(std::string bytes, const std::string& file);

// The $PhysicalNames section after its header (the same in both versions).
void read_physical_names(GmshCursor& c, GmshContent& out);

// One element's node tags after its tag and type were read; checks the type is known.
void read_element_nodes(GmshCursor& c, int type, int element_line, GmshElement& element);

} // namespace ifsim::io
