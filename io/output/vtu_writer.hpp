#pragma once
// VTK XML UnstructuredGrid files (.vtu): appended data, zlib-compressed blocks, UInt64
// headers, base64-encoded — a form ParaView 5.11 / VTK 9.1 and meshio read. (Raw appended
// bytes would be a third smaller, but Debian 12's meshio 5.0 mixes up the arrays of a raw file
// when it renumbers their offsets: an array whose new offset equals a later one's old offset.) One
// grid per file; every array is written as Float64 except the cell connectivity, offsets and types.
// Files are written atomically (temporary file, flush, rename), so a .vtu with the final name is
// complete.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace ifsim::io {

// VTK cell type codes used by ifsim.
namespace vtk_cell {
inline constexpr std::uint8_t vertex = 1;
inline constexpr std::uint8_t quad = 9;
inline constexpr std::uint8_t hexahedron = 12;
} // namespace vtk_cell

struct VtuArray {
    std::string name;
    int components = 1;
    std::vector<double> values; // tuple-major: components values per point (or cell)
    // Optional component names (ParaView shows them instead of 0, 1, ...).
    std::vector<std::string> component_names;
};

struct VtuGrid {
    std::vector<double> points;             // x y z per point (2D grids: z = 0)
    std::vector<std::int64_t> connectivity; // point indices of every cell, cell after cell
    std::vector<std::int64_t> offsets;      // end of each cell in connectivity
    std::vector<std::uint8_t> types;        // vtk_cell code per cell
    std::vector<VtuArray> point_data;
    std::vector<VtuArray> cell_data;

    std::size_t n_points() const { return points.size() / 3; }
    std::size_t n_cells() const { return types.size(); }
};

// Writes grid to path. Throws std::runtime_error naming the file (and std::invalid_argument
// when an array's length does not match its tuples).
void write_vtu(const std::filesystem::path& path, const VtuGrid& grid);

// A ParaView data collection (.pvd): the time series of one kind of file.
class PvdCollection {
public:
    explicit PvdCollection(std::filesystem::path path) : path_(std::move(path)) {}
    // Adds a dataset (file relative to the .pvd's folder) at a time. The .pvd on disk is
    // rewritten atomically (so it lists complete files only) by flush(), and by add() when the
    // count reaches a power of two: a long run's collection costs O(n log n) to keep current.
    void add(double time, const std::string& file);
    void flush() const;
    const std::filesystem::path& path() const { return path_; }
    std::size_t size() const { return entries_.size(); }

    struct Entry {
        double time;
        std::string file;
    };
    const std::vector<Entry>& entries() const { return entries_; }
    // A resumed run continues the collection it had at its checkpoint.
    void restore(std::vector<Entry> entries) { entries_ = std::move(entries); }

private:
    std::filesystem::path path_;
    std::vector<Entry> entries_;
};

} // namespace ifsim::io
