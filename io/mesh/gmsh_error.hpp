#pragma once
// The error of a Gmsh mesh file: names the FILE, the LINE where the problem stands (0 when it
// concerns the file as a whole) and what was expected. The scene reader wraps it into a
// SceneError on mesh.file.

#include <stdexcept>
#include <string>

namespace ifsim::io {

class MeshFileError : public std::runtime_error {
public:
    MeshFileError(std::string file, int line, const std::string& message);

    const std::string& file() const { return file_; }
    int line() const { return line_; }

private:
    std::string file_;
    int line_;
};

} // namespace ifsim::io
