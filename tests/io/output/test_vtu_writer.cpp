// The VTU writer read back by an independent decoder: the XML's offsets, the base64 text, the
// UInt64 compression header and the zlib blocks give back every value bit for bit, also for an
// array spread over several compression blocks; the .pvd lists its datasets in order; a wrong
// array length is refused; nothing is left under the final name when writing fails.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <zlib.h>

#include "io/output/vtu_writer.hpp"

namespace fs = std::filesystem;
using namespace ifsim::io;

namespace {

std::string read_file(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

std::string unbase64(const std::string& text, std::size_t from, std::size_t chars) {
    auto value = [](char c) -> int {
        if (c >= 'A' && c <= 'Z')
            return c - 'A';
        if (c >= 'a' && c <= 'z')
            return c - 'a' + 26;
        if (c >= '0' && c <= '9')
            return c - '0' + 52;
        if (c == '+')
            return 62;
        if (c == '/')
            return 63;
        return -1; // '='
    };
    std::string out;
    for (std::size_t i = from; i + 3 < from + chars + 1 && i + 3 < text.size() + 1; i += 4) {
        const int v[4] = {value(text[i]), value(text[i + 1]), value(text[i + 2]),
                          value(text[i + 3])};
        out += static_cast<char>((v[0] << 2) | (v[1] >> 4));
        if (v[2] >= 0)
            out += static_cast<char>(((v[1] & 15) << 4) | (v[2] >> 2));
        if (v[3] >= 0)
            out += static_cast<char>(((v[2] & 3) << 6) | v[3]);
    }
    return out;
}

std::size_t chars_for(std::size_t bytes) {
    return (bytes + 2) / 3 * 4;
}

// The uncompressed bytes of the appended array at `offset` (characters after '_').
std::string decode_array(const std::string& appended, std::size_t offset) {
    const std::string first = unbase64(appended, offset, chars_for(8));
    std::uint64_t blocks = 0;
    std::memcpy(&blocks, first.data(), 8);
    const std::size_t header_bytes = 8 * (3 + blocks);
    const std::string header = unbase64(appended, offset, chars_for(header_bytes));
    std::uint64_t h[3];
    std::memcpy(h, header.data(), 24);
    std::size_t compressed_total = 0;
    std::vector<std::uint64_t> sizes(blocks);
    for (std::size_t b = 0; b < blocks; ++b) {
        std::memcpy(&sizes[b], header.data() + 24 + 8 * b, 8);
        compressed_total += sizes[b];
    }
    const std::string body =
        unbase64(appended, offset + chars_for(header_bytes), chars_for(compressed_total));
    std::string out;
    std::size_t at = 0;
    for (std::size_t b = 0; b < blocks; ++b) {
        const std::size_t n = (b + 1 == blocks && h[2] > 0) ? h[2] : h[1];
        std::string block(n, '\0');
        uLongf len = static_cast<uLongf>(n);
        EXPECT_EQ(uncompress(reinterpret_cast<Bytef*>(block.data()), &len,
                             reinterpret_cast<const Bytef*>(body.data() + at),
                             static_cast<uLong>(sizes[b])),
                  Z_OK);
        EXPECT_EQ(len, n);
        out += block;
        at += sizes[b];
    }
    return out;
}

template <class T>
std::vector<T> as_values(const std::string& bytes) {
    std::vector<T> v(bytes.size() / sizeof(T));
    std::memcpy(v.data(), bytes.data(), v.size() * sizeof(T));
    return v;
}

} // namespace

TEST(VtuWriter, EveryArrayReadsBackBitForBit) {
    const fs::path dir = fs::temp_directory_path() / "ifsim-vtu-writer";
    fs::create_directories(dir);
    VtuGrid g;
    // Two quads sharing an edge.
    g.points = {0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0, 1, 1, 0, 2, 1, 0};
    g.connectivity = {0, 1, 4, 3, 1, 2, 5, 4};
    g.offsets = {4, 8};
    g.types = {vtk_cell::quad, vtk_cell::quad};
    VtuArray small{"t_N", 1, {-1.5, 2.25e-300, 0.1, -0.0, 1e300, 3.0}, {}};
    // 300 000 values (2.4 MB): three compression blocks of 1 MiB, the last one partial.
    VtuArray big{"big", 50000, {}, {}};
    for (int i = 0; i < 300000; ++i) {
        big.values.push_back(std::sin(0.001 * i) * 1e3 + i);
    }
    big.components = 50000;
    g.point_data = {small, big};
    g.cell_data = {VtuArray{"stress", 6, {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12}, {}}};
    const fs::path file = dir / "grid.vtu";
    write_vtu(file, g);
    EXPECT_FALSE(fs::exists(dir / "grid.vtu.partial"));

    const std::string text = read_file(file);
    const std::size_t start = text.find("<AppendedData encoding=\"base64\">\n_");
    ASSERT_NE(start, std::string::npos);
    const std::string appended = text.substr(text.find('_', start) + 1);
    std::map<std::string, std::size_t> offsets;
    const std::regex tag(
        "<DataArray type=\"([A-Za-z0-9]+)\" Name=\"([^\"]+)\"[^>]*offset=\"(\\d+)\"");
    for (auto it = std::sregex_iterator(text.begin(), text.begin() + static_cast<long>(start), tag);
         it != std::sregex_iterator(); ++it) {
        offsets[(*it)[2]] = std::stoul((*it)[3]);
    }
    ASSERT_EQ(offsets.size(), 7u); // t_N, big, stress, Points, connectivity, offsets, types
    EXPECT_EQ(as_values<double>(decode_array(appended, offsets["t_N"])), small.values);
    EXPECT_EQ(as_values<double>(decode_array(appended, offsets["big"])), big.values);
    EXPECT_EQ(as_values<double>(decode_array(appended, offsets["stress"])), g.cell_data[0].values);
    EXPECT_EQ(as_values<double>(decode_array(appended, offsets["Points"])), g.points);
    EXPECT_EQ(as_values<std::int64_t>(decode_array(appended, offsets["connectivity"])),
              g.connectivity);
    EXPECT_EQ(as_values<std::int64_t>(decode_array(appended, offsets["offsets"])), g.offsets);
    EXPECT_EQ(as_values<std::uint8_t>(decode_array(appended, offsets["types"])), g.types);
    EXPECT_NE(text.find("NumberOfPoints=\"6\" NumberOfCells=\"2\""), std::string::npos);
    fs::remove_all(dir);
}

TEST(VtuWriter, WrongArrayLengthIsRefusedAndNothingIsWritten) {
    const fs::path dir = fs::temp_directory_path() / "ifsim-vtu-writer-bad";
    fs::create_directories(dir);
    VtuGrid g;
    g.points = {0, 0, 0, 1, 0, 0};
    g.connectivity = {0, 1};
    g.offsets = {1, 2};
    g.types = {vtk_cell::vertex, vtk_cell::vertex};
    g.point_data = {VtuArray{"t_N", 1, {1.0, 2.0, 3.0}, {}}}; // three values for two points
    EXPECT_THROW(write_vtu(dir / "bad.vtu", g), std::invalid_argument);
    EXPECT_FALSE(fs::exists(dir / "bad.vtu"));
    fs::remove_all(dir);
}

TEST(PvdCollection, ListsItsDatasetsInOrderWithTheirTimes) {
    const fs::path dir = fs::temp_directory_path() / "ifsim-pvd";
    fs::create_directories(dir);
    PvdCollection pvd(dir / "mesh.pvd");
    pvd.add(0.0, "fields/mesh-000000.vtu");
    pvd.add(1.165, "fields/mesh-000100.vtu");
    pvd.add(2.0000000000000004, "fields/mesh-000200.vtu");
    // Rewritten at 1, 2, 4, ... entries and on flush(): the third waits for the flush.
    EXPECT_EQ(read_file(dir / "mesh.pvd").find("mesh-000200"), std::string::npos);
    pvd.flush();
    const std::string text = read_file(dir / "mesh.pvd");
    const auto a = text.find("timestep=\"0\"");
    const auto b =
        text.find("timestep=\"1.165\" group=\"\" part=\"0\" file=\"fields/mesh-000100.vtu\"");
    const auto c = text.find("timestep=\"2.0000000000000004\"");
    ASSERT_NE(a, std::string::npos);
    ASSERT_NE(b, std::string::npos);
    ASSERT_NE(c, std::string::npos);
    EXPECT_LT(a, b);
    EXPECT_LT(b, c);
    EXPECT_EQ(pvd.size(), 3u);
    EXPECT_FALSE(fs::exists(dir / "mesh.pvd.partial"));
    fs::remove_all(dir);
}
