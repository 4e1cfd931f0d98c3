#include "io/mesh/gmsh_parse.hpp"

#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include <fmt/format.h>

#include "io/mesh/gmsh_binary.hpp"
#include "io/mesh/gmsh_error.hpp"
#include "io/mesh/gmsh_msh22.hpp"
#include "io/mesh/gmsh_msh41.hpp"

namespace ifsim::io {

namespace {

constexpr long long max_count = std::numeric_limits<int>::max();

// $MeshFormat: "version file-type data-size"; returns the version.
std::string read_mesh_format(GmshCursor& c) {
    const std::string_view first = c.next_or_end();
    if (first != "$MeshFormat") {
        c.fail(
            fmt::format("expected a Gmsh mesh file starting with '$MeshFormat', found {}",
                        first.empty() ? std::string("an empty file") : fmt::format("'{}'", first)));
    }
    c.enter("$MeshFormat");
    const std::string version(c.token("the format version"));
    if (version != "4.1" && version != "2.2") {
        c.fail(fmt::format("expected MSH format version 4.1 or 2.2, found '{}' (save the mesh "
                           "as \"Version 4.1 ASCII\" or \"Version 2 ASCII\")",
                           version));
    }
    if (c.integer("the file type (0 = ASCII)", 0, 1) != 0) {
        c.fail("expected the ASCII form here (binary files are transcoded before parsing)");
    }
    c.integer("the data size", 1, 16);
    c.expect_end();
    return version;
}

} // namespace

void read_physical_names(GmshCursor& c, GmshContent& out) {
    const long long n = c.integer("the number of physical names", 0, max_count);
    for (long long i = 0; i < n; ++i) {
        const int dim = static_cast<int>(c.integer("a physical group's dimension", 0, 3));
        const int line = c.line();
        const int tag = static_cast<int>(c.integer("a physical group's tag", 1, max_count));
        std::string name = c.quoted("the physical group's name");
        if (name.empty()) {
            c.fail(fmt::format("expected a non-empty name for physical group {} of dimension {}",
                               tag, dim));
        }
        const auto [it, added] = out.names.try_emplace({dim, tag}, GmshName{std::move(name), line});
        if (!added) {
            c.fail(fmt::format("physical group {} of dimension {} is named twice (first on line "
                               "{})",
                               tag, dim, it->second.line));
        }
    }
    c.expect_end();
}

void read_element_nodes(GmshCursor& c, int type, int element_line, GmshElement& element) {
    const GmshElementType* info = gmsh_element_type(type);
    if (info == nullptr) {
        c.fail_at(element_line, fmt::format("element {} has the unknown Gmsh element type {}",
                                            element.tag, type));
    }
    element.type = type;
    element.line = element_line;
    element.nodes.resize(static_cast<std::size_t>(info->nodes));
    for (auto& n : element.nodes) {
        n = c.integer("a node tag of the element", 1, std::numeric_limits<long long>::max());
    }
}

GmshContent parse_gmsh_text(std::string text, const std::string& file) {
    GmshCursor c(std::move(text), file);
    GmshContent out;
    out.file = file;
    out.version = read_mesh_format(c);
    Msh41Reader v4;
    Msh22Reader v2;
    bool nodes = false;
    bool elements = false;
    for (std::string_view header = c.next_or_end(); !header.empty(); header = c.next_or_end()) {
        if (header.front() != '$' || header.starts_with("$End")) {
            c.fail(fmt::format("expected a section header such as '$Nodes' or '$Elements', "
                               "found '{}'",
                               header));
        }
        c.enter(header);
        nodes = nodes || header == "$Nodes";
        elements = elements || header == "$Elements";
        if (header == "$PhysicalNames") {
            read_physical_names(c, out);
        } else if (out.version == "4.1" ? !v4.read_section(header, c, out)
                                        : !v2.read_section(header, c, out)) {
            c.skip_section();
        }
    }
    if (!nodes || !elements) {
        c.fail_at(0, fmt::format("expected the sections $Nodes and $Elements, the file has no {}",
                                 nodes ? "$Elements" : "$Nodes"));
    }
    if (out.version == "4.1") {
        v4.finish(c, out);
    } else {
        v2.finish(out);
    }
    return out;
}

GmshContent parse_gmsh_file(const std::string& path) {
    // A device or FIFO (a scene's mesh file = "/dev/zero") would be read without end.
    std::error_code ec;
    if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec)) {
        throw MeshFileError(path, 0, "not a regular file (a directory, device or pipe)");
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        throw MeshFileError(path, 0, "cannot open the mesh file (missing or unreadable)");
    }
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) {
        throw MeshFileError(path, 0, "cannot read the mesh file");
    }
    return parse_gmsh_bytes(std::move(text).str(), path);
}

GmshContent parse_gmsh_bytes(std::string bytes, const std::string& path) {
    if (!is_binary_gmsh(bytes)) {
        return parse_gmsh_text(std::move(bytes), path);
    }
    // Binary: the same checks on its ASCII form; a line number there is not one of the file.
    std::string ascii = gmsh_binary_to_ascii(bytes, path);
    try {
        return parse_gmsh_text(std::move(ascii), path);
    } catch (const MeshFileError& e) {
        std::string message = e.what();
        const std::string prefix =
            e.line() > 0 ? fmt::format("{}:{}: ", path, e.line()) : path + ": ";
        if (message.starts_with(prefix)) {
            message.erase(0, prefix.size());
        }
        throw MeshFileError(path, e.line(),
                            message + " (binary file: the line is that of its ASCII form)");
    }
}

} // namespace ifsim::io
