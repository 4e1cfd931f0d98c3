// The checkpoint container: every value comes back bit for bit (NaN payloads, -0, denormals,
// extremes); a foreign, truncated, damaged or newer file and a missing or mistyped section are
// CheckpointErrors naming the file and the defect; no temporary file is left behind.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "io/output/checkpoint_file.hpp"

namespace fs = std::filesystem;
using namespace ifsim::io;

namespace {

fs::path scratch(const std::string& name) {
    const fs::path dir = fs::temp_directory_path() / "ifsim-checkpoint-test";
    fs::create_directories(dir);
    return dir / name;
}

std::string bytes_of(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

void write_bytes(const fs::path& p, const std::string& b) {
    std::ofstream(p, std::ios::binary | std::ios::trunc) << b;
}

template <class F>
void expect_error(const fs::path& p, const std::string& words, F&& f) {
    try {
        f();
        ADD_FAILURE() << "no error; expected: " << words;
    } catch (const CheckpointError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find(p.string()), std::string::npos) << what;
        EXPECT_NE(what.find(words), std::string::npos) << what;
    }
}

bool same_bits(double a, double b) {
    return std::memcmp(&a, &b, sizeof a) == 0;
}

} // namespace

TEST(CheckpointFile, EveryValueComesBackBitForBit) {
    double odd_nan;
    const std::uint64_t payload = 0x7ff8dead0000beefULL;
    std::memcpy(&odd_nan, &payload, 8);
    const std::vector<double> d = {0.1,      -0.0,    std::numeric_limits<double>::denorm_min(),
                                   1e308,    odd_nan, -std::numeric_limits<double>::infinity(),
                                   1.0 / 3.0};
    const std::vector<std::int64_t> i = {0, -1, std::numeric_limits<std::int64_t>::max(), 42};
    CheckpointWriter w;
    w.put("state", d);
    w.put("counters", i);
    // A scene text with a NUL inside (sizeof counts the literal's terminator: minus 1).
    static constexpr char with_nul[] = "kind = \"boundary-value\"\n\0binary";
    w.put("scene", std::string(with_nul, sizeof(with_nul) - 1));
    w.put("empty", std::vector<double>{});
    const fs::path p = scratch("round-trip.ckp");
    w.write(p);
    EXPECT_FALSE(fs::exists(fs::path(p.string() + ".partial")));
    const CheckpointReader r(p);
    const auto back = r.doubles("state");
    ASSERT_EQ(back.size(), d.size());
    for (std::size_t k = 0; k < d.size(); ++k) {
        EXPECT_TRUE(same_bits(back[k], d[k])) << k;
    }
    EXPECT_EQ(r.integers("counters"), i);
    EXPECT_EQ(r.text("scene"), std::string(with_nul, sizeof(with_nul) - 1));
    EXPECT_TRUE(r.doubles("empty").empty());
    EXPECT_TRUE(r.has("state"));
    EXPECT_FALSE(r.has("missing"));
}

TEST(CheckpointFile, DefectsAreNamedAndNothingIsUsed) {
    CheckpointWriter w;
    w.put("u", std::vector<double>{1.0, 2.0, 3.0});
    w.put("step", std::vector<std::int64_t>{7});
    const fs::path good = scratch("good.ckp");
    w.write(good);
    const std::string b = bytes_of(good);

    const fs::path foreign = scratch("foreign.ckp");
    write_bytes(foreign, "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n");
    expect_error(foreign, "not an ifsim checkpoint", [&] { CheckpointReader r(foreign); });

    const fs::path cut = scratch("cut.ckp");
    write_bytes(cut, b.substr(0, b.size() - 5));
    expect_error(cut, "truncated", [&] { CheckpointReader r(cut); });

    const fs::path flipped = scratch("flipped.ckp");
    std::string f = b;
    f[f.size() - 3] ^= 0x10; // one bit of the last value
    write_bytes(flipped, f);
    expect_error(flipped, "damaged", [&] { CheckpointReader r(flipped); });

    const fs::path newer = scratch("newer.ckp");
    std::string n = b;
    n[8] = 9; // format version
    write_bytes(newer, n);
    expect_error(newer, "format 9", [&] { CheckpointReader r(newer); });

    const CheckpointReader r(good);
    expect_error(good, "no section 'v'", [&] { r.doubles("v"); });
    expect_error(good, "holds integers, expected doubles", [&] { r.doubles("step"); });
    expect_error(good, "holds 3 values, expected one", [&] { r.real("u"); });
    EXPECT_EQ(r.integer("step"), 7);
}
