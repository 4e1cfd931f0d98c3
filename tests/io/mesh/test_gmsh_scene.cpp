// Boundary-value scenes meshed from a Gmsh file ([mesh] file, [[region]]): the shipped
// fe-simple-shear-cnl-2d-gmsh.toml builds the structured twin's mesh and writes the same
// history.csv; --set mesh.file picks another file; bad [mesh] file / [[region]] input is a
// SceneError naming the scene file and the key (and for a bad mesh the mesh file and line).

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "io/boundary_value/boundary_value_scene.hpp"
#include "io/cli/cli.hpp"
#include "io/scene/scene_error.hpp"
#include "io/scene/scene_toml.hpp"
#include "tests/io/boundary_value_test_support.hpp"
#include "tests/io/scene_test_support.hpp"

namespace ifsim::io {
namespace {

namespace fs = std::filesystem;

const char* const structured = "scenes/fe-simple-shear-cnl-2d.toml";
const char* const gmsh = "scenes/fe-simple-shear-cnl-2d-gmsh.toml";
const char* const mesh_line = "file = \"meshes/shear-box-2d.msh\"";

int run(std::vector<std::string> args) {
    return test::run_cli_captured(std::move(args)).code;
}

// The shipped gmsh scene's text with the mesh file given by its absolute path (the scene is
// written to a temporary folder).
std::string gmsh_scene_text() {
    const std::string mesh = fs::absolute("scenes/meshes/shear-box-2d.msh").string();
    return test::replaced(test::read_text(gmsh), mesh_line, "file = \"" + mesh + "\"");
}

std::vector<std::vector<std::string>> csv(const fs::path& file) {
    std::istringstream in(test::read_text(file));
    std::vector<std::vector<std::string>> rows;
    for (std::string line; std::getline(in, line);) {
        std::vector<std::string> fields;
        std::istringstream ls(line);
        for (std::string f; std::getline(ls, f, ',');) {
            fields.push_back(f);
        }
        rows.push_back(fields);
    }
    return rows;
}

TEST(GmshScene, BuildsTheStructuredTwinsMesh) {
    const BoundaryValueScene a = test::parse_boundary_value(structured);
    const BoundaryValueScene b = test::parse_boundary_value(gmsh);
    EXPECT_EQ(b.mesh_spec.file, "meshes/shear-box-2d.msh");
    EXPECT_EQ(b.mesh.type, a.mesh.type);
    EXPECT_EQ(b.mesh.coordinates, a.mesh.coordinates);
    EXPECT_EQ(b.mesh.connectivity, a.mesh.connectivity);
    // Every set the structured scene names has the same members (face sets included).
    for (const char* set : {"soil", "plate"}) {
        EXPECT_EQ(b.mesh.element_set(set), a.mesh.element_set(set)) << set;
    }
    for (const char* set : {"soil.bottom", "soil.top", "soil.left", "soil.right", "plate.top",
                            "plate.bottom", "plate.all", "soil.all"}) {
        EXPECT_EQ(b.mesh.node_set(set), a.mesh.node_set(set)) << set;
    }
    for (const char* set : {"soil.bottom", "soil.top", "plate.top", "plate.left"}) {
        EXPECT_EQ(b.mesh.face_set(set), a.mesh.face_set(set)) << set;
    }
    // Regions: materials by element set, in region order, bounding boxes as the bodies'.
    ASSERT_EQ(b.bodies.size(), 2u);
    EXPECT_EQ(b.bodies[1].name, "plate");
    EXPECT_EQ(b.bodies[1].material, "steel");
    EXPECT_EQ(b.bodies[0].origin, a.bodies[0].origin);
    EXPECT_DOUBLE_EQ(b.bodies[0].top(), a.bodies[0].top());
    ASSERT_EQ(b.set_materials().size(), 2u);
    EXPECT_EQ(b.set_materials()[0].element_set, "soil");
    EXPECT_EQ(b.set_materials()[0].initial_state, a.set_materials()[0].initial_state);
    EXPECT_EQ(b.contacts.at(0).slave_body, "soil");
}

TEST(GmshScene, SameHistoryAsTheStructuredScene) {
    const fs::path da = test::fresh_dir("gmsh-twin-a");
    const fs::path db = test::fresh_dir("gmsh-twin-b");
    const std::vector<std::string> shorter = {"--set", "stage.2.steps=60", "--set",
                                              "stage.2.displacement.1.change=0.0015"};
    std::vector<std::string> a = {"run", structured, "--out", da.string()};
    std::vector<std::string> b = {"run", gmsh, "--out", db.string()};
    a.insert(a.end(), shorter.begin(), shorter.end());
    b.insert(b.end(), shorter.begin(), shorter.end());
    ASSERT_EQ(run(a), 0);
    ASSERT_EQ(run(b), 0);
    const auto ha = csv(da / "history.csv");
    const auto hb = csv(db / "history.csv");
    ASSERT_GE(ha.size(), 63u); // header, row 0, consolidation, 60 shear increments (or more)
    ASSERT_EQ(hb.size(), ha.size());
    EXPECT_EQ(hb[0], ha[0]);
    for (std::size_t r = 1; r < ha.size(); ++r) {
        ASSERT_EQ(hb[r].size(), ha[r].size()) << "row " << r;
        for (std::size_t c = 0; c < ha[r].size(); ++c) {
            if (ha[r][c].empty() || hb[r][c].empty()) {
                EXPECT_EQ(hb[r][c], ha[r][c]) << ha[0][c] << " row " << r;
                continue;
            }
            const double x = std::stod(ha[r][c]);
            EXPECT_NEAR(std::stod(hb[r][c]), x, 1e-12 * std::max(1.0, std::abs(x)))
                << ha[0][c] << " row " << r;
        }
    }
    // The shear really happened: t_t1 grew.
    const auto col = std::find(ha[0].begin(), ha[0].end(), "t_t1") - ha[0].begin();
    EXPECT_GT(std::stod(hb.back()[static_cast<std::size_t>(col)]), 10.0);
    EXPECT_NE(test::read_text(db / "summary.json").find("shear-box-2d.msh"), std::string::npos);
}

TEST(GmshScene, SetMeshFilePicksAnotherFile) {
    // The soil split into two quadrangles (an extra node pair at x = 0.05), in MSH 2.2 (the
    // plate written once per physical group), in a folder of its own: the override gives its
    // absolute path.
    const fs::path dir = test::fresh_dir("gmsh-set");
    const fs::path mesh = dir / "split.msh";
    std::ofstream(mesh) << R"($MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
8
1 11 "soil.bottom"
1 12 "soil.right"
1 13 "soil.top"
1 14 "soil.left"
1 23 "plate.top"
2 1 "soil"
2 2 "plate"
2 4 "plate.all"
$EndPhysicalNames
$Nodes
10
1 0 0 0
2 0.1 0 0
3 0 0.02 0
4 0.1 0.02 0
5 -0.01 -0.01 0
6 0.11 -0.01 0
7 -0.01 0 0
8 0.11 0 0
9 0.05 0 0
10 0.05 0.02 0
$EndNodes
$Elements
11
1 1 2 11 1 1 9
2 1 2 11 1 9 2
3 1 2 13 3 4 10
4 1 2 13 3 10 3
5 1 2 23 7 8 7
6 3 2 1 1 1 9 10 3
7 3 2 1 1 9 2 4 10
8 3 2 2 2 5 6 8 7
9 3 2 4 2 5 6 8 7
10 1 2 12 2 2 4
11 1 2 14 4 3 1
$EndElements
)";
    const BoundaryValueScene s = test::parse_boundary_value(gmsh, {"mesh.file=" + mesh.string()});
    EXPECT_EQ(s.mesh.element_set("soil").size(), 2u);
    EXPECT_EQ(s.mesh.face_set("soil.bottom").size(), 2u);
    EXPECT_EQ(s.mesh.node_set("soil.top").size(), 3u);
    EXPECT_EQ(s.mesh.node_set("plate.all").size(), 4u);
    EXPECT_EQ(s.mesh.n_nodes(), 10);
}

TEST(GmshScene, BadInputNamesFileAndKey) {
    const std::string text = gmsh_scene_text();
    // A region naming a set the file does not have.
    test::expect_boundary_value_error(test::replaced(text, "set = \"plate\"", "set = \"steel\""),
                                      "region.2.set",
                                      {"element set of the mesh", "\"steel\"", "\"plate\""});
    test::expect_boundary_value_error(
        test::replaced(text, "material = \"steel\"", "material = \"iron\""), "region.2.material",
        {"[material.NAME]", "\"iron\""});
    // Elements left without a material, or given two.
    test::expect_boundary_value_error(
        test::replaced(text, "[[region]]\nset = \"plate\"\nmaterial = \"steel\"\n", ""), "region",
        {"every element a material", "element 1", "\"plate\""});
    test::expect_boundary_value_error(test::replaced(text, "set = \"plate\"", "set = \"soil.all\""),
                                      "region.2.set", {"sharing no element", "region 1"});
    // Exactly one of [mesh] file and [[body]].
    test::expect_boundary_value_error(
        text + "\n[[body]]\nname = \"x\"\nmaterial = \"sand\"\norigin = [0.0, 0.0]\n"
               "size = [1.0, 1.0]\nelements = [1, 1]\n",
        "body", {"not both"});
    test::expect_boundary_value_error(
        test::replaced(
            test::replaced(text, "[[region]]\nset = \"plate\"\nmaterial = \"steel\"\n", ""),
            "[[region]]\nset = \"soil\"\nmaterial = \"sand\"\n", ""),
        "region", {"missing", "[[region]]"});
    test::expect_boundary_value_error(
        test::replaced(test::read_text(structured), "[material.sand]",
                       "[[region]]\nset = \"soil\"\nmaterial = \"sand\"\n\n[material.sand]"),
        "region", {"mesh file"});
    // The dimension must be the file's.
    test::expect_boundary_value_error(test::replaced(text, "dimension = 2", "dimension = 3"),
                                      "mesh.dimension", {"shear-box-2d.msh", "(2)"});
    // A missing or bad mesh file: the scene's key, the mesh file and its line.
    const std::string shipped = fs::absolute("scenes/meshes/shear-box-2d.msh").string();
    test::expect_boundary_value_error(test::replaced(text, shipped, shipped + ".none"), "mesh.file",
                                      {shipped + ".none: cannot open"});
    const fs::path bad = test::fresh_dir("gmsh-bad") / "bad.msh";
    std::string mesh = test::read_text("scenes/meshes/shear-box-2d.msh");
    std::ofstream(bad) << test::replaced(mesh, "2 2 3 1\n10 5 6 8 7", "2 2 2 1\n10 5 6 8");
    const std::string bad_line = std::to_string(
        1 +
        std::count(mesh.begin(), mesh.begin() + static_cast<long>(mesh.find("10 5 6 8 7")), '\n'));
    test::expect_boundary_value_error(
        test::replaced(text, fs::absolute("scenes/meshes/shear-box-2d.msh").string(), bad.string()),
        "mesh.file", {bad.string() + ":" + bad_line + ":", "3-node triangle"});
}

} // namespace
} // namespace ifsim::io
