#pragma once
// Gmsh binary mesh files (MSH 4.1 and 2.2, file type 1, what Gmsh writes with "Save all
// options > binary" or `-bin`): transcoded into the equivalent ASCII text, which the ASCII
// parser (gmsh_parse.hpp) then reads and checks as it reads every mesh, so that both forms go
// through the same validation. Sections the reader does not use are passed over.

#include <string>

namespace ifsim::io {

// Whether the file's $MeshFormat says file type 1 (binary).
bool is_binary_gmsh(const std::string& bytes);

// The ASCII form of a binary MSH file. Throws MeshFileError naming the file for a truncated
// file, another data size than 8 bytes, a byte order other than the machine's (little
// endian), or a section that does not end where its data says.
std::string gmsh_binary_to_ascii(const std::string& bytes, const std::string& file);

} // namespace ifsim::io
