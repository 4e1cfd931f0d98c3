#include "io/output/checkpoint_file.hpp"

#include "io/output/atomic_file.hpp"

#include <cstring>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <zlib.h>

namespace ifsim::io {
namespace {

constexpr char magic[8] = {'I', 'F', 'S', 'I', 'M', 'C', 'K', 'P'};
constexpr std::uint8_t kind_doubles = 1, kind_integers = 2, kind_text = 3;
const char* const kind_names[] = {"?", "doubles", "integers", "text"};

template <class T>
void append(std::string& out, const T& v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    out.append(b, sizeof(T));
}

void append_section(std::string& out, const std::string& name, std::uint8_t kind, const void* data,
                    std::uint64_t bytes) {
    append(out, static_cast<std::uint32_t>(name.size()));
    out += name;
    append(out, kind);
    append(out, bytes);
    out.append(static_cast<const char*>(data), bytes);
}

std::uint32_t crc(const std::string& s) {
    return static_cast<std::uint32_t>(
        crc32(0L, reinterpret_cast<const Bytef*>(s.data()), static_cast<uInt>(s.size())));
}

} // namespace

void CheckpointWriter::put(const std::string& name, std::span<const double> values) {
    append_section(payload_, name, kind_doubles, values.data(), values.size_bytes());
}

void CheckpointWriter::put(const std::string& name, std::span<const std::int64_t> values) {
    append_section(payload_, name, kind_integers, values.data(), values.size_bytes());
}

void CheckpointWriter::put(const std::string& name, const std::string& text) {
    append_section(payload_, name, kind_text, text.data(), text.size());
}

void CheckpointWriter::write(const std::filesystem::path& path) const {
    std::string header(magic, sizeof magic);
    append(header, CheckpointReader::format_version);
    append(header, static_cast<std::uint64_t>(payload_.size()));
    append(header, crc(payload_));
    write_file_atomically(path, header, payload_, true);
}

CheckpointReader::CheckpointReader(const std::filesystem::path& path) : file_(path.string()) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        throw CheckpointError(fmt::format("{}: cannot open the checkpoint", file_));
    }
    std::ostringstream buf;
    buf << in.rdbuf();
    const std::string all = std::move(buf).str();
    constexpr std::size_t header = sizeof magic + 4 + 8 + 4;
    if (all.size() < header || std::memcmp(all.data(), magic, sizeof magic) != 0) {
        throw CheckpointError(fmt::format("{}: not an ifsim checkpoint", file_));
    }
    std::uint32_t version = 0, sum = 0;
    std::uint64_t size = 0;
    std::memcpy(&version, all.data() + 8, 4);
    std::memcpy(&size, all.data() + 12, 8);
    std::memcpy(&sum, all.data() + 20, 4);
    if (version != format_version) {
        throw CheckpointError(fmt::format("{}: checkpoint format {} (this ifsim reads {})", file_,
                                          version, format_version));
    }
    if (all.size() != header + size) {
        throw CheckpointError(fmt::format("{}: truncated or extended checkpoint ({} bytes, the "
                                          "header says {})",
                                          file_, all.size(), header + size));
    }
    const std::string payload = all.substr(header);
    if (crc(payload) != sum) {
        throw CheckpointError(fmt::format("{}: damaged checkpoint (checksum mismatch)", file_));
    }
    std::size_t at = 0;
    const auto take = [&](void* dst, std::size_t n) {
        if (at + n > payload.size()) {
            throw CheckpointError(fmt::format("{}: malformed checkpoint section", file_));
        }
        std::memcpy(dst, payload.data() + at, n);
        at += n;
    };
    while (at < payload.size()) {
        std::uint32_t name_size = 0;
        take(&name_size, 4);
        std::string name(name_size, '\0');
        take(name.data(), name_size);
        Section s;
        std::uint64_t bytes = 0;
        take(&s.kind, 1);
        take(&bytes, 8);
        if (bytes > payload.size() - at) {
            throw CheckpointError(
                fmt::format("{}: malformed checkpoint section '{}'", file_, name));
        }
        s.bytes = payload.substr(at, bytes);
        at += bytes;
        sections_[name] = std::move(s);
    }
}

const CheckpointReader::Section& CheckpointReader::section(const std::string& name,
                                                           std::uint8_t kind) const {
    const auto it = sections_.find(name);
    if (it == sections_.end()) {
        throw CheckpointError(fmt::format("{}: the checkpoint has no section '{}'", file_, name));
    }
    if (it->second.kind != kind) {
        throw CheckpointError(fmt::format("{}: section '{}' holds {}, expected {}", file_, name,
                                          kind_names[std::min<int>(it->second.kind, 3)],
                                          kind_names[kind]));
    }
    return it->second;
}

std::vector<double> CheckpointReader::doubles(const std::string& name) const {
    const Section& s = section(name, kind_doubles);
    std::vector<double> v(s.bytes.size() / sizeof(double));
    if (!v.empty()) { // memcpy from or to a null pointer is undefined even for 0 bytes
        std::memcpy(v.data(), s.bytes.data(), v.size() * sizeof(double));
    }
    return v;
}

std::vector<std::int64_t> CheckpointReader::integers(const std::string& name) const {
    const Section& s = section(name, kind_integers);
    std::vector<std::int64_t> v(s.bytes.size() / sizeof(std::int64_t));
    if (!v.empty()) { // memcpy from or to a null pointer is undefined even for 0 bytes
        std::memcpy(v.data(), s.bytes.data(), v.size() * sizeof(std::int64_t));
    }
    return v;
}

std::string CheckpointReader::text(const std::string& name) const {
    return section(name, kind_text).bytes;
}

double CheckpointReader::real(const std::string& name) const {
    const auto v = doubles(name);
    if (v.size() != 1) {
        throw CheckpointError(
            fmt::format("{}: section '{}' holds {} values, expected one", file_, name, v.size()));
    }
    return v[0];
}

std::int64_t CheckpointReader::integer(const std::string& name) const {
    const auto v = integers(name);
    if (v.size() != 1) {
        throw CheckpointError(
            fmt::format("{}: section '{}' holds {} values, expected one", file_, name, v.size()));
    }
    return v[0];
}

} // namespace ifsim::io
