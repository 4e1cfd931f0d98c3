#include "io/mesh/gmsh_error.hpp"

#include <fmt/format.h>

namespace ifsim::io {

namespace {

std::string located(const std::string& file, int line, const std::string& message) {
    return line > 0 ? fmt::format("{}:{}: {}", file, line, message)
                    : fmt::format("{}: {}", file, message);
}

} // namespace

MeshFileError::MeshFileError(std::string file, int line, const std::string& message)
    : std::runtime_error(located(file, line, message)), file_(std::move(file)), line_(line) {}

} // namespace ifsim::io
