// Outputs that are not tied to a horizontal shear box (docs/scenes.md "Outputs", "Recorders"):
// a linear-elastic block between a fixed left wall and a right wall moved downwards (both
// Coulomb). The pairs' shear columns follow their shear direction (global x would read 0), the
// per-pair relative displacements and forces are consistent with the tractions, a node
// recorder reads the prescribed wall motion, and a point recorder picks the point nearest to
// its position.
#include <cmath>

#include <gtest/gtest.h>

#include "tests/io/boundary_value_test_support.hpp"

namespace ifsim::io {
namespace {

namespace fs = std::filesystem;

const std::string walls_scene = R"(
kind = "boundary-value"

[mesh]
dimension = 2

[[body]]
name = "soil"
material = "soil"
origin = [0.0, 0.0]
size = [0.2, 0.2]
elements = [4, 4]

[[body]]
name = "wall"
material = "steel"
origin = [0.2, -0.02]
size = [0.01, 0.24]
elements = [1, 6]

[[body]]
name = "left"
material = "steel"
origin = [-0.01, -0.02]
size = [0.01, 0.24]
elements = [1, 6]

[material.soil]
model = "linear-elastic"
parameters = { E = 2.0e4, nu = 0.3 }
stress = [-50.0, -100.0, -50.0, 0.0, 0.0, 0.0]

[material.steel]
model = "linear-elastic"
parameters = { E = 2.1e8, nu = 0.3 }

[[contact]]
name = "moving"
slave = "soil.right"
master = "wall.left"
formulation = "coulomb"
friction_coefficient = 0.3
tangential_stiffness = 1.0e5
shear_direction = [0.0, -1.0, 0.0]

[[contact]]
name = "fixed"
slave = "soil.left"
master = "left.right"
formulation = "coulomb"
friction_coefficient = 0.3
tangential_stiffness = 1.0e5
shear_direction = [0.0, -1.0, 0.0]

[output]
plate = "wall.all"
soil_top = "soil.top"
contact = "moving"

[[recorder]]
name = "wall_down"
nodes = "wall.all"
direction = [0.0, -2.0]

[[recorder]]
name = "mid"
contact = "moving"
position = [0.2, 0.1]

[[stage]]
name = "hold"
steps = 1
displacement = [ { nodes = "wall.all", direction = "x" }, { nodes = "wall.all", direction = "y" },
                 { nodes = "left.all", direction = "x" }, { nodes = "left.all", direction = "y" },
                 { nodes = "soil.bottom", direction = "y" } ]
pressure = [ { faces = "soil.top", from = 100.0 } ]

[[stage]]
name = "down"
steps = 10
displacement = [ { nodes = "wall.all", direction = "x" },
                 { nodes = "wall.all", direction = "y", change = -0.001 },
                 { nodes = "left.all", direction = "x" }, { nodes = "left.all", direction = "y" },
                 { nodes = "soil.bottom", direction = "y" } ]
pressure = [ { faces = "soil.top", from = 100.0 } ]
)";

TEST(BoundaryValueOutputs, PairFrameAndRecordersFollowAWallMovedDownwards) {
    const std::string scene = test::write_scene(walls_scene, "walls");
    const fs::path dir = test::fresh_dir("walls-run");
    const auto r = test::run_cli_captured({"run", scene, "--out", dir.string(), "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    const test::History h = test::read_history(dir);
    const std::size_t last = h.rows.size() - 1;
    // The soil slides along the moving wall: the shear along t1 = down is the friction limit
    // (the global x component would be 0).
    const double t_n = h.number(last, "t_n");
    EXPECT_LT(t_n, -40.0);
    EXPECT_NEAR(h.number(last, "t_t1"), 0.3 * std::abs(t_n), 1e-3 * std::abs(t_n));
    EXPECT_NEAR(h.number(last, "moving.t_t1"), h.number(last, "t_t1"), 1e-12);
    EXPECT_EQ(h.number(last, "t_t2"), 0.0);
    // Relative displacements in the pairs' frames: the wall 1 mm down against the soil, which
    // is dragged down a little near it (measured 0.86 mm of relative motion); no opening.
    EXPECT_GT(h.number(last, "moving.u_t1"), 0.5e-3);
    EXPECT_LT(h.number(last, "moving.u_t1"), 1.0e-3);
    EXPECT_NEAR(h.number(last, "moving.u_n"), 0.0, 1e-5);
    EXPECT_NEAR(h.number(last, "fixed.u_t1"), 0.0, 1e-4); // the left wall and soil stay
    EXPECT_GT(h.number(last, "u_t1"), 0.5e-3);            // plate (wall) minus soil top
    // Forces: mean traction times the active area (the face length per m, in the current
    // configuration of the pairing: within the soil's strain of 0.2 m).
    const double area = h.number(last, "moving.F_n") / h.number(last, "moving.t_n");
    EXPECT_NEAR(area, 0.2, 2e-3);
    EXPECT_NEAR(h.number(last, "moving.F_t1"), area * h.number(last, "moving.t_t1"), 1e-9);
    // Row 0: the initial stress on the faces, no displacement.
    EXPECT_DOUBLE_EQ(h.number(0, "moving.t_n"), -50.0);
    EXPECT_DOUBLE_EQ(h.number(0, "moving.F_n"), -10.0);
    EXPECT_EQ(h.number(0, "wall_down"), 0.0);
    EXPECT_EQ(h.rows[0].at("mid.t_n"), "");
    // The node recorder: the prescribed motion along the normalised direction.
    EXPECT_NEAR(h.number(last, "wall_down"), 1.0e-3, 1e-15);
    EXPECT_NEAR(h.number(6, "wall_down"), 0.5e-3, 1e-15); // row 6: 5 of 10 increments
    // The point recorder: a Gauss point of the right face near mid-height, sliding.
    const double pt_n = h.number(last, "mid.t_n");
    EXPECT_LT(pt_n, 0.0);
    EXPECT_NEAR(h.number(last, "mid.t_t1"), 0.3 * std::abs(pt_n), 1e-3 * std::abs(pt_n));
    EXPECT_EQ(h.rows[last].at("mid.s_p1"), ""); // Coulomb: no interface band
    const nlohmann::json s = test::summary(dir);
    const auto& p = s["point_recorders"].at(0);
    EXPECT_EQ(p["name"], "mid");
    EXPECT_NEAR(p["position"][0].get<double>(), 0.2, 1e-12);
    EXPECT_NEAR(p["position"][1].get<double>(), 0.1, 0.03);
    bool described = false;
    for (const auto& c : s["columns"]) {
        if (c["name"] == "wall_down") {
            EXPECT_EQ(c["unit"], "m");
            described = true;
        }
    }
    EXPECT_TRUE(described);
}

// A shear direction normal to the faces (the default +x on these walls) falls back to the
// vertical axis: the same history as shear_direction = [0, 1, 0] (the vertical of 2D).
TEST(BoundaryValueOutputs, ShearDirectionNormalToTheFacesFallsBackToTheVertical) {
    std::string text = walls_scene;
    for (int k = 0; k < 2; ++k) {
        text = test::replaced(text, "shear_direction = [0.0, -1.0, 0.0]",
                              "shear_direction = [0.0, 1.0, 0.0]");
    }
    const std::string up = test::write_scene(text, "walls-up");
    const std::string normal =
        test::write_scene(test::replaced(text, "shear_direction = [0.0, 1.0, 0.0]\n\n[[contact]]",
                                         "shear_direction = [1.0, 0.0, 0.0]\n\n[[contact]]"),
                          "walls-normal");
    const fs::path a = test::fresh_dir("walls-up-run"), b = test::fresh_dir("walls-normal-run");
    ASSERT_EQ(test::run_cli_captured({"run", up, "--out", a.string(), "-q"}).code, 0);
    ASSERT_EQ(test::run_cli_captured({"run", normal, "--out", b.string(), "-q"}).code, 0);
    const test::History ha = test::read_history(a), hb = test::read_history(b);
    const std::size_t last = ha.rows.size() - 1;
    EXPECT_EQ(ha.rows[last].at("t_t1"), hb.rows[last].at("t_t1"));
    EXPECT_LT(hb.number(last, "t_t1"), 0.0); // up along the wall: the wall drags the soil down
}

TEST(BoundaryValueOutputs, BadRecordersNameFileAndKey) {
    test::expect_boundary_value_error(
        test::replaced(walls_scene, "nodes = \"wall.all\"", "nodes = \"wall.everything\""),
        "recorder.1.nodes", "node set");
    test::expect_boundary_value_error(test::replaced(walls_scene, "contact = \"moving\"\nposition",
                                                     "contact = \"sliding\"\nposition"),
                                      "recorder.2.contact", "\"moving\", \"fixed\"");
    test::expect_boundary_value_error(
        test::replaced(walls_scene, "name = \"mid\"", "name = \"wall_down\""), "recorder.2.name",
        "new name");
    test::expect_boundary_value_error(
        test::replaced(walls_scene, "direction = [0.0, -2.0]", "direction = [0.0, 0.0]"),
        "recorder.1.direction", "non-zero");
    test::expect_boundary_value_error(
        test::replaced(walls_scene, "name = \"wall_down\"", "name = \"time\""), "recorder.1.name",
        "column");
    test::expect_boundary_value_error(
        test::replaced(walls_scene, "name = \"mid\"", "name = \"fixed\""), "recorder.2.name",
        "pair");
}

} // namespace
} // namespace ifsim::io
