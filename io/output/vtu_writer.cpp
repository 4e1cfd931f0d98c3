#include "io/output/vtu_writer.hpp"

#include "io/output/atomic_file.hpp"

#include <cstring>
#include <fstream>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>
#include <zlib.h>

namespace ifsim::io {
namespace {

// VTK's compressed layout for header_type UInt64: [blocks, block size, size of a partial last
// block (0: the last block is full), compressed size of each block], then the blocks.
constexpr std::size_t block_size = 1 << 20;

void append_u64(std::string& out, std::uint64_t v) {
    char b[8];
    std::memcpy(b, &v, 8); // the file says LittleEndian; x86-64 and arm64 are
    out.append(b, 8);
}

std::string base64(const std::string& in) {
    static constexpr char table[] =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((in.size() + 2) / 3 * 4);
    std::size_t i = 0;
    for (; i + 2 < in.size(); i += 3) {
        const auto a = static_cast<unsigned char>(in[i]);
        const auto b = static_cast<unsigned char>(in[i + 1]);
        const auto c = static_cast<unsigned char>(in[i + 2]);
        out += table[a >> 2];
        out += table[((a & 3) << 4) | (b >> 4)];
        out += table[((b & 15) << 2) | (c >> 6)];
        out += table[c & 63];
    }
    if (i < in.size()) {
        const auto a = static_cast<unsigned char>(in[i]);
        const bool two = i + 1 < in.size();
        const auto b = two ? static_cast<unsigned char>(in[i + 1]) : 0;
        out += table[a >> 2];
        out += table[((a & 3) << 4) | (b >> 4)];
        out += two ? table[(b & 15) << 2] : '=';
        out += '=';
    }
    return out;
}

// The header and the compressed blocks of one array, each base64-encoded on its own (VTK's
// layout for compressed base64 data).
std::string compressed(const void* data, std::size_t bytes, const std::string& file) {
    const std::size_t full = bytes / block_size;
    const std::size_t last = bytes % block_size;
    const std::size_t blocks = full + (last > 0 ? 1 : 0);
    std::string header;
    append_u64(header, blocks);
    append_u64(header, block_size);
    append_u64(header, last);
    std::string body;
    const auto* src = static_cast<const Bytef*>(data);
    for (std::size_t b = 0; b < blocks; ++b) {
        const std::size_t n = (b + 1 == blocks && last > 0) ? last : block_size;
        uLongf size = compressBound(static_cast<uLong>(n));
        std::string out(size, '\0');
        if (compress2(reinterpret_cast<Bytef*>(out.data()), &size, src + b * block_size,
                      static_cast<uLong>(n), Z_DEFAULT_COMPRESSION) != Z_OK) {
            throw std::runtime_error(fmt::format("cannot compress a data array of {}", file));
        }
        out.resize(size);
        append_u64(header, size);
        body += out;
    }
    return base64(header) + base64(body);
}

std::string xml_escape(const std::string& s) {
    std::string out;
    for (char c : s) {
        switch (c) {
        case '&':
            out += "&amp;";
            break;
        case '<':
            out += "&lt;";
            break;
        case '>':
            out += "&gt;";
            break;
        case '"':
            out += "&quot;";
            break;
        default:
            out += c;
        }
    }
    return out;
}

class Appended {
public:
    explicit Appended(std::string file) : file_(std::move(file)) {}
    // The DataArray element of an array whose bytes are appended.
    std::string array(const std::string& type, const std::string& name, int components,
                      const void* data, std::size_t bytes,
                      const std::vector<std::string>& component_names = {}) {
        std::string attrs = fmt::format("type=\"{}\"", type);
        if (!name.empty()) {
            attrs += fmt::format(" Name=\"{}\"", xml_escape(name));
        }
        if (components > 1) {
            attrs += fmt::format(" NumberOfComponents=\"{}\"", components);
        }
        for (std::size_t c = 0; c < component_names.size(); ++c) {
            attrs += fmt::format(" ComponentName{}=\"{}\"", c, xml_escape(component_names[c]));
        }
        const std::size_t offset = data_.size();
        data_ += compressed(data, bytes, file_);
        return fmt::format("<DataArray {} format=\"appended\" offset=\"{}\"/>\n", attrs, offset);
    }
    const std::string& data() const { return data_; }

private:
    std::string file_;
    std::string data_;
};

void check_length(const VtuArray& a, std::size_t tuples, const char* where) {
    if (a.components < 1 || a.values.size() != tuples * static_cast<std::size_t>(a.components)) {
        throw std::invalid_argument(fmt::format("{} array '{}': {} values for {} tuples of {}",
                                                where, a.name, a.values.size(), tuples,
                                                a.components));
    }
}

} // namespace

void write_vtu(const std::filesystem::path& path, const VtuGrid& grid) {
    const std::string file = path.string();
    if (grid.points.size() % 3 != 0 || grid.offsets.size() != grid.types.size() ||
        (!grid.offsets.empty() &&
         grid.offsets.back() != static_cast<std::int64_t>(grid.connectivity.size()))) {
        throw std::invalid_argument(fmt::format("inconsistent grid for {}", file));
    }
    Appended appended(file);
    std::string xml;
    xml += "<?xml version=\"1.0\"?>\n";
    xml += "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
           "header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\">\n";
    xml += "<UnstructuredGrid>\n";
    xml += fmt::format("<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", grid.n_points(),
                       grid.n_cells());
    xml += "<PointData>\n";
    for (const VtuArray& a : grid.point_data) {
        check_length(a, grid.n_points(), "point");
        xml += appended.array("Float64", a.name, a.components, a.values.data(),
                              a.values.size() * sizeof(double), a.component_names);
    }
    xml += "</PointData>\n<CellData>\n";
    for (const VtuArray& a : grid.cell_data) {
        check_length(a, grid.n_cells(), "cell");
        xml += appended.array("Float64", a.name, a.components, a.values.data(),
                              a.values.size() * sizeof(double), a.component_names);
    }
    xml += "</CellData>\n<Points>\n";
    xml += appended.array("Float64", "Points", 3, grid.points.data(),
                          grid.points.size() * sizeof(double));
    xml += "</Points>\n<Cells>\n";
    xml += appended.array("Int64", "connectivity", 1, grid.connectivity.data(),
                          grid.connectivity.size() * sizeof(std::int64_t));
    xml += appended.array("Int64", "offsets", 1, grid.offsets.data(),
                          grid.offsets.size() * sizeof(std::int64_t));
    xml += appended.array("UInt8", "types", 1, grid.types.data(), grid.types.size());
    xml += "</Cells>\n</Piece>\n</UnstructuredGrid>\n";
    xml += "<AppendedData encoding=\"base64\">\n_";

    write_file_atomically(path, xml, appended.data() + "\n</AppendedData>\n</VTKFile>\n");
}

void PvdCollection::add(double time, const std::string& file) {
    entries_.push_back({time, file});
    const std::size_t n = entries_.size();
    if ((n & (n - 1)) == 0) {
        flush();
    }
}

void PvdCollection::flush() const {
    std::string xml = "<?xml version=\"1.0\"?>\n"
                      "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
                      "<Collection>\n";
    for (const Entry& e : entries_) {
        // Shortest round-trip form of the time: the history's time column to the bit.
        xml += fmt::format("<DataSet timestep=\"{}\" group=\"\" part=\"0\" file=\"{}\"/>\n", e.time,
                           xml_escape(e.file));
    }
    xml += "</Collection>\n</VTKFile>\n";
    write_file_atomically(path_, xml);
}

} // namespace ifsim::io
