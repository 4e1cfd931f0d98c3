// Boundary-value scenes with several contact pairs ([[contact]]): two elastic blocks sliding on
// one plate with different Coulomb friction coefficients, each pair's columns in history.csv,
// [output] contact choosing the main columns, per-pair summary details, --set reaching an
// entry, and bad input naming the file and the key.

#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "io/boundary_value/boundary_value_scene.hpp"
#include "io/scene/scene_error.hpp"
#include "io/scene/scene_toml.hpp"
#include "tests/io/boundary_value_test_support.hpp"
#include "tests/io/scene_test_support.hpp"

namespace ifsim::io {
namespace {

namespace fs = std::filesystem;

// Blocks "a" (x 0.05..0.15) and "b" (x 0.35..0.45) overlap the plate by 1 micrometre
// (k_N g = -100 kPa), are pressed by 100 kPa and pushed 0.1 m along +x.
std::string two_block_scene(const std::string& output_contact) {
    std::string s = R"(kind = "boundary-value"

[mesh]
dimension = 2
integration = "full"

[[body]]
name = "a"
material = "rubber"
origin = [0.05, -1.0e-6]
size = [0.1, 0.05]
elements = [2, 1]

[[body]]
name = "b"
material = "rubber"
origin = [0.35, -1.0e-6]
size = [0.1, 0.05]
elements = [2, 1]

[[body]]
name = "plate"
material = "steel"
origin = [0.0, -0.02]
size = [0.8, 0.02]
elements = [16, 1]

[material.rubber]
model = "linear-elastic"
parameters = { E = 1.0e6, nu = 0.3 }

[material.steel]
model = "linear-elastic"
parameters = { E = 2.1e8, nu = 0.3 }

[[contact]]
name = "left"
slave = "a.bottom"
master = "plate.top"
initial_contact = "geometric"
formulation = "coulomb"
friction_coefficient = 0.2
tangential_stiffness = 1.0e6

[[contact]]
name = "right"
slave = "b.bottom"
master = "plate.top"
initial_contact = "geometric"
formulation = "coulomb"
friction_coefficient = 0.3
tangential_stiffness = 1.0e6

[output]
plate = "plate.all"
soil_top = "a.top"
)";
    if (!output_contact.empty()) {
        s += "contact = \"" + output_contact + "\"\n";
    }
    for (const auto& [name, change] : {std::pair{"press", "0.0"}, std::pair{"slide", "0.1"}}) {
        s += std::string("\n[[stage]]\nname = \"") + name +
             "\"\nsteps = " + (std::string(name) == "press" ? "2" : "20") +
             "\ndisplacement = [ { nodes = \"plate.all\", direction = \"x\" },\n"
             "  { nodes = \"plate.all\", direction = \"y\" },\n"
             "  { nodes = \"a.top\", direction = \"x\", change = " +
             change + " },\n  { nodes = \"b.top\", direction = \"x\", change = " + change +
             " } ]\nequal = [ { nodes = \"a.top\", direction = \"y\" }, { nodes = \"b.top\", "
             "direction = \"y\" } ]\npressure = [ { faces = \"a.top\", from = 100.0, to = 100.0 "
             "},\n  { faces = \"b.top\", from = 100.0, to = 100.0 } ]\n";
    }
    return s;
}

struct History {
    std::vector<std::string> names;
    std::vector<std::vector<std::string>> rows;
    std::size_t column(const std::string& name) const {
        const auto it = std::find(names.begin(), names.end(), name);
        EXPECT_NE(it, names.end()) << name;
        return static_cast<std::size_t>(it - names.begin());
    }
    double number(std::size_t row, const std::string& name) const {
        return std::stod(rows.at(row).at(column(name)));
    }
};

History read_history(const fs::path& dir) {
    std::istringstream in(test::read_text(dir / "history.csv"));
    History h;
    std::string line;
    while (std::getline(in, line)) {
        std::vector<std::string> cells;
        std::istringstream ls(line);
        for (std::string c; std::getline(ls, c, ',');) {
            cells.push_back(c);
        }
        if (line.ends_with(",")) {
            cells.emplace_back();
        }
        if (h.names.empty()) {
            h.names = cells;
        } else {
            EXPECT_EQ(cells.size(), h.names.size()) << line;
            h.rows.push_back(cells);
        }
    }
    return h;
}

BoundaryValueScene parse_text(const std::string& text, const std::vector<std::string>& sets = {}) {
    const std::string file = test::write_scene(text);
    toml::table t = load_scene_table(file);
    for (const auto& s : sets) {
        apply_override(t, s, file);
    }
    return read_boundary_value_scene(t, file);
}

TEST(BoundaryValueContacts, EntriesAreReadInOrderAndSetReachesThem) {
    const BoundaryValueScene s =
        parse_text(two_block_scene(""), {"contact.2.friction_coefficient=0.4"});
    ASSERT_EQ(s.contacts.size(), 2u);
    EXPECT_EQ(s.contacts[0].pair.name, "left");
    EXPECT_EQ(s.contacts[1].pair.name, "right");
    EXPECT_EQ(s.contacts[0].pair.slave_faces, "a.bottom");
    EXPECT_EQ(s.contacts[1].slave_body, "b");
    EXPECT_DOUBLE_EQ(s.contacts[0].pair.friction.friction_coefficient, 0.2);
    EXPECT_DOUBLE_EQ(s.contacts[1].pair.friction.friction_coefficient, 0.4);
    EXPECT_FALSE(s.contacts[1].pair.prestressed);
    // The defaults of [interface]: k_N.
    EXPECT_DOUBLE_EQ(s.contacts[1].pair.normal_penalty, 1.0e8);
    ASSERT_NE(s.main_contact(), nullptr);
    EXPECT_EQ(s.main_contact()->pair.name, "left"); // the first pair by default
    EXPECT_EQ(parse_text(two_block_scene("right")).main_contact()->pair.name, "right");
}

TEST(BoundaryValueContacts, BadEntriesNameFileAndKey) {
    const std::string text = two_block_scene("");
    test::expect_boundary_value_error(test::replaced(text, "name = \"right\"", "name = \"left\""),
                                      "contact.2.name", "not used by another");
    test::expect_boundary_value_error(
        test::replaced(text, "name = \"right\"", "name = \"right side\""), "contact.2.name",
        "[A-Za-z0-9_-]+");
    test::expect_boundary_value_error(test::replaced(text, "name = \"right\"\n", ""),
                                      "contact.2.name", "missing");
    test::expect_boundary_value_error(
        test::replaced(text, "[output]",
                       "[interface]\nslave = \"a.bottom\"\nmaster = \"plate.top\"\n\n[output]"),
        "contact", "[interface]");
    test::expect_boundary_value_error(two_block_scene("middle"), "output.contact",
                                      "\"left\", \"right\"");
    // The per-pair keys are [interface]'s, checked the same way.
    test::expect_boundary_value_error(
        test::replaced(text, "slave = \"b.bottom\"", "slave = \"b.under\""), "contact.2.slave",
        "face set");
    test::expect_boundary_value_error(
        test::replaced(text, "friction_coefficient = 0.3", "roughness = 0.3"),
        "contact.2.roughness", "coulomb");
    test::expect_boundary_value_error(
        test::replaced(text, "friction_coefficient = 0.3", "colour = 1"), "contact.2.colour",
        "unknown key");
}

// Each pair slides with its own mu: t_t1 / t_n = mu of the pair (t_t1 opposes the +x motion of
// the slave block, t_n < 0); the main columns are the pair named by [output] contact.
TEST(BoundaryValueContacts, TwoBlocksSlideEachWithItsOwnFriction) {
    const fs::path dir = test::fresh_dir("bv-contacts");
    const std::string file = test::write_scene(two_block_scene("right"));
    const test::CliRun r = test::run_cli_captured(
        {"run", file, "--out", dir.string(), "--set", "contact.2.friction_coefficient=0.4"});
    ASSERT_EQ(r.code, 0) << r.err;
    const History h = read_history(dir);
    for (const char* pair : {"left", "right"}) {
        for (const char* c : {"t_n", "t_t1", "t_t2", "closed_points", "u_n", "u_t1", "u_t2", "F_n",
                              "F_t1", "F_t2"}) {
            h.column(std::string(pair) + "." + c);
        }
    }
    ASSERT_EQ(h.names.size(), 18u + 20u);
    EXPECT_EQ(h.names[18], "left.t_n");
    ASSERT_EQ(h.rows.size(), 23u); // row 0, 2 press, 20 slide
    const std::size_t last = h.rows.size() - 1;
    for (const auto& [pair, mu] : {std::pair{"left", 0.2}, std::pair{"right", 0.4}}) {
        const std::string p(pair);
        const double t_n = h.number(last, p + ".t_n");
        EXPECT_NEAR(t_n, -100.0, 1.0) << p;
        EXPECT_LT(h.number(last, p + ".t_t1"), 0.0) << p;
        EXPECT_NEAR(h.number(last, p + ".t_t1") / t_n, mu, 1e-3 * mu) << p;
        EXPECT_GT(h.number(last, p + ".closed_points"), 0.0) << p;
        EXPECT_DOUBLE_EQ(h.number(last, p + ".t_t2"), 0.0) << p;
    }
    // [output] contact = "right": the main columns are the right pair's.
    for (std::size_t row = 0; row < h.rows.size(); ++row) {
        EXPECT_EQ(h.rows[row][h.column("t_n")], h.rows[row][h.column("right.t_n")]) << row;
        EXPECT_EQ(h.rows[row][h.column("t_t1")], h.rows[row][h.column("right.t_t1")]) << row;
        EXPECT_EQ(h.rows[row][h.column("closed_points")],
                  h.rows[row][h.column("right.closed_points")])
            << row;
    }
    // Coulomb friction: no continuum interface columns.
    EXPECT_EQ(h.rows[last][h.column("s_p1")], "");

    const nlohmann::json s = nlohmann::json::parse(test::read_text(dir / "summary.json"));
    EXPECT_EQ(s["status"], "ok");
    EXPECT_FALSE(s.contains("interface"));
    ASSERT_EQ(s["contacts"].size(), 2u);
    EXPECT_EQ(s["contacts"][0]["name"], "left");
    EXPECT_EQ(s["contacts"][1]["name"], "right");
    EXPECT_EQ(s["contacts"][1]["slave"], "b.bottom");
    EXPECT_EQ(s["contacts"][1]["formulation"], "coulomb");
    EXPECT_DOUBLE_EQ(s["contacts"][1]["friction_coefficient"].get<double>(), 0.4);
    EXPECT_EQ(s["history_contact"], "right");
    EXPECT_GT(s["counters"]["contact_evaluations"].get<long>(), 0);
}

// One pair: no per-pair columns, "interface" in the summary as before.
TEST(BoundaryValueContacts, OnePairKeepsTheColumnsAndTheSummary) {
    const fs::path dir = test::fresh_dir("bv-one-pair");
    ASSERT_EQ(test::run_cli_captured({"run", "scenes/fe-sliding-block-2d.toml", "--out",
                                      dir.string(), "--set", "stage.2.steps=4", "--set",
                                      "stage.2.displacement.3.change=0.02"})
                  .code,
              0);
    const History h = read_history(dir);
    EXPECT_EQ(h.names.size(), 18u);
    const nlohmann::json s = nlohmann::json::parse(test::read_text(dir / "summary.json"));
    EXPECT_EQ(s["interface"]["formulation"], "coulomb");
    ASSERT_EQ(s["contacts"].size(), 1u);
    EXPECT_EQ(s["contacts"][0]["name"], "interface");
}

} // namespace
} // namespace ifsim::io
