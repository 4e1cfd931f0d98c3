#pragma once
// A result file that appears complete or not at all: written to PATH.partial, optionally
// fsync'ed (checkpoints), then renamed to PATH. On failure the temporary file is removed and
// std::runtime_error names the file.

#include <filesystem>
#include <string_view>

namespace ifsim::io {

void write_file_atomically(const std::filesystem::path& path, std::string_view head,
                           std::string_view body = {}, bool sync = false);

} // namespace ifsim::io
