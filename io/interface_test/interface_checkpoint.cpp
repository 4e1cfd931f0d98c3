#include "io/interface_test/interface_checkpoint.hpp"

#include <cstdint>
#include <vector>

#include <fmt/format.h>

namespace ifsim::io {

void write_interface_test_checkpoint(const std::filesystem::path& dir,
                                     const InterfaceTestCheckpoint& c) {
    CheckpointWriter w;
    RunCheckpointHeader header = c.run;
    header.kind = "interface-test";
    put_run_header(w, header);
    const InterfaceTestPosition& p = c.position;
    w.put("position", std::vector<std::int64_t>{p.stage, p.step_in_stage, p.step});
    w.put("sample", p.sample_state);
    w.put("interface", p.interface_state);
    w.put("plate", std::vector<double>{p.u_t[0], p.u_t[1], p.slip[0], p.slip[1], p.eps11,
                                       p.guess_g[0], p.guess_g[1], p.guess_e11});
    w.write(dir / checkpoint_file_name);
}

InterfaceTestCheckpoint read_interface_test_checkpoint(const std::filesystem::path& dir) {
    const std::filesystem::path file = dir / checkpoint_file_name;
    const CheckpointReader r(file);
    InterfaceTestCheckpoint c;
    c.run = read_run_header(r, file, "interface-test");
    const auto pos = r.integers("position");
    const auto plate = r.doubles("plate");
    if (pos.size() != 3 || pos[0] < 0 || pos[1] < 0 || pos[2] < 0 || plate.size() != 8) {
        throw CheckpointError(fmt::format("{}: malformed position section", file.string()));
    }
    InterfaceTestPosition& p = c.position;
    p.stage = static_cast<int>(pos[0]);
    p.step_in_stage = static_cast<int>(pos[1]);
    p.step = static_cast<int>(pos[2]);
    p.sample_state = r.doubles("sample");
    p.interface_state = r.doubles("interface");
    p.u_t[0] = plate[0];
    p.u_t[1] = plate[1];
    p.slip[0] = plate[2];
    p.slip[1] = plate[3];
    p.eps11 = plate[4];
    p.guess_g[0] = plate[5];
    p.guess_g[1] = plate[6];
    p.guess_e11 = plate[7];
    return c;
}

} // namespace ifsim::io
