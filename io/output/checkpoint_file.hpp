#pragma once
// The container of a checkpoint (docs/scenes.md, "Checkpoint and resume"): named sections of
// doubles, 64-bit integers or text, stored bit for bit, behind a magic, a format version and a
// CRC-32 of the content. Written atomically (temporary file, fsync, rename, fsync of the
// folder), so a checkpoint on disk is either the previous one or the new one, whole. Reading
// refuses a foreign, damaged, truncated or newer file with CheckpointError, before anything
// is used.

#include <cstdint>
#include <filesystem>
#include <map>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace ifsim::io {

class CheckpointError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

class CheckpointWriter {
public:
    void put(const std::string& name, std::span<const double> values);
    void put(const std::string& name, std::span<const std::int64_t> values);
    void put(const std::string& name, const std::string& text);
    // Writes the sections to path atomically. Throws std::runtime_error naming the file.
    void write(const std::filesystem::path& path) const;

private:
    std::string payload_;
};

class CheckpointReader {
public:
    // Reads and checks the whole file. Throws CheckpointError naming the file and the defect.
    explicit CheckpointReader(const std::filesystem::path& path);

    bool has(const std::string& name) const { return sections_.contains(name); }
    // A section of the given kind; throws CheckpointError naming the section when it is
    // missing or of another kind.
    std::vector<double> doubles(const std::string& name) const;
    std::vector<std::int64_t> integers(const std::string& name) const;
    std::string text(const std::string& name) const;
    double real(const std::string& name) const; // a one-value section
    std::int64_t integer(const std::string& name) const;

    static constexpr std::uint32_t format_version = 1;

private:
    struct Section {
        std::uint8_t kind = 0;
        std::string bytes;
    };
    const Section& section(const std::string& name, std::uint8_t kind) const;

    std::string file_;
    std::map<std::string, Section> sections_;
};

} // namespace ifsim::io
