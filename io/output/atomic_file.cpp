#include "io/output/atomic_file.hpp"

#include <fstream>
#include <stdexcept>
#include <system_error>

#include <fcntl.h>
#include <unistd.h>

#include <fmt/format.h>

namespace ifsim::io {
namespace {

// fsync of a file or folder by path; false on failure.
bool sync_path(const std::filesystem::path& p, bool directory) {
    const int fd = ::open(p.c_str(), directory ? O_RDONLY | O_DIRECTORY : O_RDONLY);
    if (fd < 0) {
        return false;
    }
    const bool ok = ::fsync(fd) == 0;
    ::close(fd);
    return ok;
}

} // namespace

void write_file_atomically(const std::filesystem::path& path, std::string_view head,
                           std::string_view body, bool sync) {
    std::filesystem::path tmp = path;
    tmp += ".partial";
    std::error_code ec;
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        out.write(head.data(), static_cast<std::streamsize>(head.size()));
        out.write(body.data(), static_cast<std::streamsize>(body.size()));
        out.flush();
        if (!out) {
            out.close();
            std::filesystem::remove(tmp, ec); // no partial file left behind
            throw std::runtime_error(fmt::format("cannot write {}", tmp.string()));
        }
    }
    if (sync && !sync_path(tmp, false)) {
        std::filesystem::remove(tmp, ec);
        throw std::runtime_error(fmt::format("cannot flush {} to disk", tmp.string()));
    }
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        throw std::runtime_error(
            fmt::format("cannot rename {} to {}: {}", tmp.string(), path.string(), ec.message()));
    }
    if (sync) { // the rename itself; best effort where folders cannot be synced
        sync_path(path.has_parent_path() ? path.parent_path() : std::filesystem::path("."), true);
    }
}

} // namespace ifsim::io
