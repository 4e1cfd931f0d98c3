#include "io/scene/scene_error.hpp"

#include <fmt/format.h>

namespace ifsim::io {

namespace {

std::string format_message(const std::string& file, const std::string& key,
                           const std::string& expected, int line) {
    const std::string where = line > 0 ? fmt::format("{}:{}", file, line) : file;
    if (key.empty()) {
        return fmt::format("{}: {}", where, expected);
    }
    return fmt::format("{}: {}: {}", where, key, expected);
}

} // namespace

SceneError::SceneError(std::string file, std::string key, std::string expected, int line)
    : std::runtime_error(format_message(file, key, expected, line)), file_(std::move(file)),
      key_(std::move(key)), expected_(std::move(expected)), line_(line) {}

} // namespace ifsim::io
