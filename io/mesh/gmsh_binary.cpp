#include "io/mesh/gmsh_binary.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <limits>
#include <sstream>
#include <string_view>

#include <fmt/format.h>

#include "io/mesh/gmsh_content.hpp"
#include "io/mesh/gmsh_error.hpp"

namespace ifsim::io {
namespace {

// Bytes of the file shown in a message: printable ASCII as is, others as \xNN (a message
// goes into summary.json, which must stay valid UTF-8).
std::string shown(std::string_view bytes) {
    std::string out;
    for (char c : bytes.substr(0, 40)) {
        const auto u = static_cast<unsigned char>(c);
        out += (u >= 0x20 && u < 0x7f) ? std::string(1, c) : fmt::format("\\x{:02x}", u);
    }
    return out;
}

// A count written as text (MSH 2.2): digits only, within what the reader takes.
long long text_count(const std::string& word, const char* what, const auto& fail) {
    long long v = -1;
    const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), v);
    if (ec != std::errc() || end != word.data() + word.size() || v < 0 ||
        v > std::numeric_limits<int>::max()) {
        fail(fmt::format("expected {} (a count), found '{}'", what, shown(word)));
    }
    return v;
}

// Reads the binary file: text lines (section headers, counts of MSH 2.2) and binary values.
class ByteReader {
public:
    ByteReader(const std::string& bytes, const std::string& file) : b_(bytes), file_(file) {}

    bool at_end() {
        skip_space();
        return pos_ >= b_.size();
    }
    // The next whitespace-delimited word.
    std::string word(const char* what) {
        skip_space();
        const std::size_t start = pos_;
        while (pos_ < b_.size() && !std::isspace(static_cast<unsigned char>(b_[pos_]))) {
            ++pos_;
        }
        if (start == pos_) {
            fail(fmt::format("expected {}, found the end of the file", what));
        }
        return b_.substr(start, pos_ - start);
    }
    // Binary data follows the line break after a header or count.
    void skip_line_break() {
        while (pos_ < b_.size() && b_[pos_] != '\n') {
            ++pos_;
        }
        ++pos_;
    }
    template <class T>
    T value(const char* what) {
        if (pos_ + sizeof(T) > b_.size()) {
            fail(
                fmt::format("truncated: expected {} ({} bytes) at byte {}", what, sizeof(T), pos_));
        }
        T v;
        std::memcpy(&v, b_.data() + pos_, sizeof(T));
        pos_ += sizeof(T);
        return v;
    }
    // Passes over an unused section up to its "$End<name>".
    void skip_to(const std::string& end) {
        const std::size_t at = b_.find(end, pos_);
        if (at == std::string::npos) {
            fail(fmt::format("expected '{}', found the end of the file", end));
        }
        pos_ = at + end.size();
    }
    // The ASCII text of a section written as text in binary files too ($PhysicalNames).
    std::string text_to(const std::string& end) {
        const std::size_t at = b_.find(end, pos_);
        if (at == std::string::npos) {
            fail(fmt::format("expected '{}', found the end of the file", end));
        }
        std::string t = b_.substr(pos_, at - pos_);
        pos_ = at + end.size();
        return t;
    }
    void expect(const std::string& end) {
        const std::string w = word(end.c_str());
        if (w != end) {
            fail(fmt::format("expected '{}' after the section's binary data, found '{}' (a "
                             "count in the file does not match its data)",
                             end, shown(w)));
        }
    }
    [[noreturn]] void fail(const std::string& message) const {
        throw MeshFileError(file_, 0, fmt::format("binary mesh file: {}", message));
    }

private:
    void skip_space() {
        while (pos_ < b_.size() && std::isspace(static_cast<unsigned char>(b_[pos_]))) {
            ++pos_;
        }
    }
    const std::string& b_;
    const std::string& file_;
    std::size_t pos_ = 0;
};

void entities_41(ByteReader& r, std::string& out) {
    std::uint64_t counts[4];
    for (auto& n : counts) {
        n = r.value<std::uint64_t>("the number of entities of a dimension");
    }
    out += fmt::format("{} {} {} {}\n", counts[0], counts[1], counts[2], counts[3]);
    for (int dim = 0; dim < 4; ++dim) {
        for (std::uint64_t i = 0; i < counts[dim]; ++i) {
            out += fmt::format("{}", r.value<std::int32_t>("an entity tag"));
            for (int k = 0; k < (dim == 0 ? 3 : 6); ++k) {
                out += fmt::format(" {}", r.value<double>("a coordinate"));
            }
            const auto np = r.value<std::uint64_t>("the number of physical tags");
            out += fmt::format(" {}", np);
            for (std::uint64_t k = 0; k < np; ++k) {
                out += fmt::format(" {}", r.value<std::int32_t>("a physical tag"));
            }
            if (dim > 0) {
                const auto nb = r.value<std::uint64_t>("the number of bounding entities");
                out += fmt::format(" {}", nb);
                for (std::uint64_t k = 0; k < nb; ++k) {
                    out += fmt::format(" {}", r.value<std::int32_t>("a bounding entity tag"));
                }
            }
            out += "\n";
        }
    }
}

void nodes_41(ByteReader& r, std::string& out) {
    const auto blocks = r.value<std::uint64_t>("the number of node blocks");
    const auto n = r.value<std::uint64_t>("the number of nodes");
    const auto lo = r.value<std::uint64_t>("the smallest node tag");
    const auto hi = r.value<std::uint64_t>("the largest node tag");
    out += fmt::format("{} {} {} {}\n", blocks, n, lo, hi);
    for (std::uint64_t b = 0; b < blocks; ++b) {
        const auto dim = r.value<std::int32_t>("an entity dimension");
        const auto tag = r.value<std::int32_t>("an entity tag");
        const auto parametric = r.value<std::int32_t>("the parametric flag");
        const auto count = r.value<std::uint64_t>("the number of nodes in the block");
        out += fmt::format("{} {} {} {}\n", dim, tag, parametric, count);
        for (std::uint64_t k = 0; k < count; ++k) {
            out += fmt::format("{}\n", r.value<std::uint64_t>("a node tag"));
        }
        // x y z, and with the parametric flag up to 3 parametric coordinates (by dimension).
        const int per_node = 3 + (parametric != 0 ? std::max(0, static_cast<int>(dim)) : 0);
        for (std::uint64_t k = 0; k < count; ++k) {
            for (int c = 0; c < per_node; ++c) {
                out += fmt::format("{}{}", c > 0 ? " " : "", r.value<double>("a coordinate"));
            }
            out += "\n";
        }
    }
}

void elements_41(ByteReader& r, std::string& out) {
    const auto blocks = r.value<std::uint64_t>("the number of element blocks");
    const auto n = r.value<std::uint64_t>("the number of elements");
    const auto lo = r.value<std::uint64_t>("the smallest element tag");
    const auto hi = r.value<std::uint64_t>("the largest element tag");
    out += fmt::format("{} {} {} {}\n", blocks, n, lo, hi);
    for (std::uint64_t b = 0; b < blocks; ++b) {
        const auto dim = r.value<std::int32_t>("an entity dimension");
        const auto tag = r.value<std::int32_t>("an entity tag");
        const auto type = r.value<std::int32_t>("an element type");
        const auto count = r.value<std::uint64_t>("the number of elements in the block");
        const GmshElementType* info = gmsh_element_type(type);
        if (info == nullptr) {
            r.fail(
                fmt::format("element block {} has the unknown Gmsh element type {}", b + 1, type));
        }
        out += fmt::format("{} {} {} {}\n", dim, tag, type, count);
        for (std::uint64_t k = 0; k < count; ++k) {
            out += fmt::format("{}", r.value<std::uint64_t>("an element tag"));
            for (int a = 0; a < info->nodes; ++a) {
                out += fmt::format(" {}", r.value<std::uint64_t>("a node tag of an element"));
            }
            out += "\n";
        }
    }
}

void nodes_22(ByteReader& r, std::string& out) {
    const std::string count = r.word("the number of nodes");
    r.skip_line_break();
    const long long n =
        text_count(count, "the number of nodes", [&](const std::string& m) { r.fail(m); });
    out += count + "\n";
    for (long long k = 0; k < n; ++k) {
        out += fmt::format("{}", r.value<std::int32_t>("a node number"));
        for (int c = 0; c < 3; ++c) {
            out += fmt::format(" {}", r.value<double>("a coordinate"));
        }
        out += "\n";
    }
}

// MSH 2.2 binary elements come in blocks of one type: type, count, number of tags.
void elements_22(ByteReader& r, std::string& out) {
    const std::string count = r.word("the number of elements");
    r.skip_line_break();
    const long long n =
        text_count(count, "the number of elements", [&](const std::string& m) { r.fail(m); });
    out += count + "\n";
    long long done = 0;
    while (done < n) {
        const auto type = r.value<std::int32_t>("an element type");
        const auto follow = r.value<std::int32_t>("the number of elements that follow");
        const auto tags = r.value<std::int32_t>("the number of tags");
        const GmshElementType* info = gmsh_element_type(type);
        if (info == nullptr || follow <= 0 || tags < 0) {
            r.fail(fmt::format("bad element block header (type {}, {} elements, {} tags)", type,
                               follow, tags));
        }
        for (int k = 0; k < follow; ++k) {
            out += fmt::format("{} {} {}", r.value<std::int32_t>("an element number"), type, tags);
            for (int t = 0; t < tags; ++t) {
                out += fmt::format(" {}", r.value<std::int32_t>("an element tag"));
            }
            for (int a = 0; a < info->nodes; ++a) {
                out += fmt::format(" {}", r.value<std::int32_t>("a node number of an element"));
            }
            out += "\n";
        }
        done += follow;
    }
}

} // namespace

bool is_binary_gmsh(const std::string& bytes) {
    std::istringstream in(bytes.substr(0, 256));
    std::string head, version;
    int type = 0;
    return (in >> head >> version >> type) && head == "$MeshFormat" && type == 1;
}

std::string gmsh_binary_to_ascii(const std::string& bytes, const std::string& file) {
    ByteReader r(bytes, file);
    if (r.word("'$MeshFormat'") != "$MeshFormat") {
        r.fail("expected a Gmsh mesh file starting with '$MeshFormat'");
    }
    const std::string version = r.word("the format version");
    r.word("the file type");
    const std::string size = r.word("the data size");
    if (version != "4.1" && version != "2.2") {
        r.fail(fmt::format("expected MSH format version 4.1 or 2.2, found '{}'", shown(version)));
    }
    if (size != "8") {
        r.fail(
            fmt::format("expected 8-byte size_t (data size 8), found data size {}", shown(size)));
    }
    r.skip_line_break();
    const auto marker = r.value<std::int32_t>("the byte-order marker (int 1)");
    char as_text[4];
    std::memcpy(as_text, &marker, 4);
    if (std::string_view(as_text, 4) == "$End") {
        r.fail("the file says file type 1 (binary) but holds text: a text file needs file type "
               "0 in $MeshFormat");
    }
    if (marker != 1) {
        r.fail("the file's byte order is not this machine's (written on a big-endian machine)");
    }
    r.expect("$EndMeshFormat");
    std::string out = fmt::format("$MeshFormat\n{} 0 8\n$EndMeshFormat\n", version);
    while (!r.at_end()) {
        const std::string header = r.word("a section header");
        if (header.empty() || header.front() != '$' || header.starts_with("$End")) {
            r.fail(fmt::format("expected a section header such as '$Nodes', found '{}'",
                               shown(header)));
        }
        const std::string end = "$End" + header.substr(1);
        if (header == "$PhysicalNames") { // text in binary files too
            out += header + r.text_to(end) + end + "\n";
            continue;
        }
        const bool used = header == "$Entities" || header == "$Nodes" || header == "$Elements";
        if (!used) {
            r.skip_to(end);
            continue;
        }
        out += header + "\n";
        if (version == "4.1") {
            r.skip_line_break();
            if (header == "$Entities") {
                entities_41(r, out);
            } else if (header == "$Nodes") {
                nodes_41(r, out);
            } else {
                elements_41(r, out);
            }
        } else if (header == "$Nodes") {
            nodes_22(r, out);
        } else if (header == "$Elements") {
            elements_22(r, out);
        } else {
            r.skip_to(end);
            out.resize(out.size() - header.size() - 1);
            continue;
        }
        r.expect(end);
        out += end + "\n";
    }
    return out;
}

} // namespace ifsim::io
