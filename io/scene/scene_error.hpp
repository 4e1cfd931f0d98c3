#pragma once
// The one error type of scene input: it names the scene FILE, the KEY (dotted path, array
// entries counted from 1 like the stages in history.csv) and WHAT WAS EXPECTED, so a user can
// fix the scene without reading code. Optionally the line in the file where the value stands.

#include <stdexcept>
#include <string>

namespace ifsim::io {

class SceneError : public std::runtime_error {
public:
    SceneError(std::string file, std::string key, std::string expected, int line = 0);

    const std::string& file() const { return file_; }
    const std::string& key() const { return key_; }
    const std::string& expected() const { return expected_; }
    int line() const { return line_; }

private:
    std::string file_;
    std::string key_;
    std::string expected_;
    int line_;
};

} // namespace ifsim::io
