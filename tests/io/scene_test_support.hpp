#pragma once
// Helpers of the io tests: scenes written to fresh temporary files, and a minimal valid
// element-test scene to vary.

#include <atomic>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <vector>

#include <gtest/gtest.h>
#include <unistd.h>

#include "io/cli/cli.hpp"

namespace ifsim::io::test {

// `ifsim ARGS...` through the command-line entry point, with its exit code and what it printed.
struct CliRun {
    int code = 0;
    std::string err;
    std::string out;
};

inline CliRun run_cli_captured(std::vector<std::string> args) {
    args.insert(args.begin(), "ifsim");
    std::vector<const char*> argv;
    for (const auto& a : args) {
        argv.push_back(a.c_str());
    }
    testing::internal::CaptureStderr();
    testing::internal::CaptureStdout();
    const int code = run_cli(static_cast<int>(argv.size()), argv.data());
    std::string out = testing::internal::GetCapturedStdout();
    return {code, testing::internal::GetCapturedStderr(), out};
}

// Directories made by fresh_dir(), removed when the test program ends.
struct TempDirs {
    std::vector<std::filesystem::path> dirs;
    ~TempDirs() {
        for (const auto& d : dirs) {
            std::error_code ec;
            std::filesystem::remove_all(d, ec);
        }
    }
};

// A fresh directory for one test (removed and re-created).
inline std::filesystem::path fresh_dir(const std::string& name) {
    static std::atomic<int> counter{0};
    static TempDirs made;
    const auto dir =
        std::filesystem::temp_directory_path() / ("ifsim-io-test-" + std::to_string(::getpid()) +
                                                  "-" + name + "-" + std::to_string(counter++));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    made.dirs.push_back(dir);
    return dir;
}

inline std::string write_scene(const std::string& text, const std::string& name = "scene") {
    const auto path = fresh_dir(name) / (name + ".toml");
    std::ofstream(path) << text;
    return path.string();
}

inline std::string read_text(const std::filesystem::path& path) {
    std::ifstream in(path);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Material, initial state and stages of a small valid hypoplastic scene; tests append or
// replace pieces.
inline const std::string hypo_material = R"(
[material]
model = "hypoplasticity"
parameters = "karlsruhe-sand"
)";
inline const std::string hypo_initial = R"(
[initial]
stress = [-100.0, -50.0, -50.0, 0.0, 0.0, 0.0]
void_ratio = 0.7
)";
inline const std::string oedometer_stage = R"(
[[stage]]
steps = 20
deps_11 = -0.001
deps_22 = 0.0
deps_33 = 0.0
deps_12 = 0.0
deps_13 = 0.0
deps_23 = 0.0
)";
inline const std::string triaxial_stage = R"(
[[stage]]
steps = 10
deps_11 = -0.002
dsig_22 = 0.0
dsig_33 = 0.0
deps_12 = 0.0
deps_13 = 0.0
deps_23 = 0.0
)";

inline std::string valid_scene() {
    return "kind = \"element-test\"\n" + hypo_material + hypo_initial + oedometer_stage +
           triaxial_stage;
}

} // namespace ifsim::io::test
