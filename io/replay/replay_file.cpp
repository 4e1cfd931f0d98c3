#include "io/replay/replay_file.hpp"

#include <sstream>

#include <fmt/format.h>

#include "io/output/atomic_file.hpp"

namespace ifsim::io {

toml::array replay_numbers(std::span<const double> values) {
    toml::array a;
    for (double v : values) {
        a.push_back(v);
    }
    return a;
}

std::filesystem::path write_replay(const std::filesystem::path& dir, const toml::table& scene,
                                   const std::string& what_failed, bool simd,
                                   const std::string& name, const std::string& outcome) {
    const std::filesystem::path path = dir / name;
    std::ostringstream text;
    text << fmt::format("# Replay: {}\n#\n# ifsim run {} --out REPLAY_DIR{}\n# {} "
                        "(docs/reliability.md, \"Replaying a failed point\"); the run used the "
                        "{} path.\n\n",
                        what_failed, path.string(), simd ? "" : " --scalar", outcome,
                        simd ? "SIMD" : "scalar");
    text << scene << '\n';
    write_file_atomically(path, text.str());
    return path;
}

} // namespace ifsim::io
