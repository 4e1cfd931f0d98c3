#include "io/element_test/element_checkpoint.hpp"

#include <cstdint>
#include <vector>

#include <fmt/format.h>

namespace ifsim::io {

void write_element_test_checkpoint(const std::filesystem::path& dir,
                                   const ElementTestCheckpoint& c) {
    CheckpointWriter w;
    RunCheckpointHeader header = c.run;
    header.kind = "element-test";
    put_run_header(w, header);
    const ElementTestPosition& p = c.position;
    w.put("position", std::vector<std::int64_t>{p.stage, p.step_in_stage, p.step});
    w.put("state", p.state);
    w.put("strain", p.strain);
    w.put("guess", p.guess);
    w.put("stress_start", p.stress_start);
    w.write(dir / checkpoint_file_name);
}

ElementTestCheckpoint read_element_test_checkpoint(const std::filesystem::path& dir) {
    const std::filesystem::path file = dir / checkpoint_file_name;
    const CheckpointReader r(file);
    ElementTestCheckpoint c;
    c.run = read_run_header(r, file, "element-test");
    const auto pos = r.integers("position");
    const auto six = [&](const char* name) {
        const auto v = r.doubles(name);
        if (v.size() != 6) {
            throw CheckpointError(
                fmt::format("{}: section {} has {} values, not 6", file.string(), name, v.size()));
        }
        Sym<double> out{};
        std::copy(v.begin(), v.end(), out.begin());
        return out;
    };
    if (pos.size() != 3 || pos[0] < 0 || pos[1] < 0 || pos[2] < 0) {
        throw CheckpointError(fmt::format("{}: malformed position section", file.string()));
    }
    ElementTestPosition& p = c.position;
    p.stage = static_cast<int>(pos[0]);
    p.step_in_stage = static_cast<int>(pos[1]);
    p.step = static_cast<int>(pos[2]);
    p.state = r.doubles("state");
    p.strain = six("strain");
    p.guess = six("guess");
    p.stress_start = six("stress_start");
    return c;
}

} // namespace ifsim::io
