// Gmsh mesh files (io/mesh/gmsh_reader.hpp): 2D and 3D MSH 4.1 and 2D MSH 2.2 files written here
// become fem meshes with the physical groups as element, face and node sets, boundary elements
// matched to their element's local face, inverted elements mirrored, node tags with gaps
// numbered densely; bad files are MeshFileErrors naming the file and the line.

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "fem/mesh.hpp"
#include "io/mesh/gmsh_error.hpp"
#include "io/mesh/gmsh_reader.hpp"
#include "tests/io/scene_test_support.hpp"

namespace ifsim::io {
namespace {

std::string write_msh(const std::string& text, const std::string& name = "mesh") {
    const auto path = test::fresh_dir(name) / (name + ".msh");
    std::ofstream(path) << text;
    return path.string();
}

// 1-based line of the first occurrence of `marker` in `text`.
int line_of(const std::string& text, const std::string& marker) {
    const auto at = text.find(marker);
    EXPECT_NE(at, std::string::npos) << marker;
    return 1 +
           static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n'));
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return text.replace(at, from.size(), to);
}

// Reading `text` fails at `line` (0: no line) with a message containing `words` and the file.
void expect_mesh_error(const std::string& text, int line, const std::string& words) {
    const std::string file = write_msh(text);
    try {
        read_gmsh_mesh(file);
        ADD_FAILURE() << "no error; expected one with: " << words;
    } catch (const MeshFileError& e) {
        EXPECT_EQ(e.file(), file);
        EXPECT_EQ(e.line(), line) << e.what();
        const std::string what = e.what();
        EXPECT_NE(what.find(words), std::string::npos) << what;
        const std::string where = line > 0 ? file + ":" + std::to_string(line) + ":" : file + ":";
        EXPECT_EQ(what.rfind(where, 0), 0u) << what;
    }
}

// Signed area of a quad4 (positive counter-clockwise).
double signed_area(const fem::Mesh& m, int e) {
    double a = 0.0;
    for (int i = 0; i < 4; ++i) {
        const int p = m.node(e, i);
        const int q = m.node(e, (i + 1) % 4);
        a += m.coordinate(p, 0) * m.coordinate(q, 1) - m.coordinate(q, 0) * m.coordinate(p, 1);
    }
    return 0.5 * a;
}

// Two unit squares side by side, x in [0, 2], y in [0, 1]. Node tags 2, 4, 6 (bottom) and
// 10, 12, 14 (top) plus an unused node 99 on a parametric curve block; element 7 (the right
// square) is clockwise. Groups: surfaces "left" (tag 1), unnamed 2, "soil" (5, both); curves
// "bottom" (both bottom edges, one reversed), "top" (the left square's), unnamed 13 (the
// right side); point "corner" (node 2); a point element in no group (node 14).
const std::string two_quads_41 = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
5
0 20 "corner"
1 11 "bottom"
1 12 "top"
2 1 "left"
2 5 "soil"
$EndPhysicalNames
$Entities
2 4 2 0
1 0 0 0 1 20
2 2 1 0 0
1 0 0 0 1 0 0 1 11 0
2 1 0 0 2 0 0 1 11 0
3 0 1 0 1 1 0 1 12 0
4 2 0 0 2 1 0 1 13 0
1 0 0 0 1 1 0 2 1 5 0
2 1 0 0 2 1 0 2 2 5 0
$EndEntities
$Nodes
2 7 2 99
2 1 0 6
2
4
6
10
12
14
0 0 0
1 0 0
2 0 0
0 1 0
1 1 0
2 1 0
1 3 1 1
99
5 5 0 0.5
$EndNodes
$Elements
8 8 7 100
0 1 15 1
50 2
0 2 15 1
51 14
1 1 1 1
60 2 4
1 2 1 1
61 6 4
1 3 1 1
62 12 10
1 4 1 1
63 6 14
2 1 3 1
100 2 4 12 10
2 2 3 1
7 4 12 14 6
$EndElements
)";

TEST(GmshReader, Reads2dMsh41GroupsAsSets) {
    const GmshMesh g = read_gmsh_mesh(write_msh(two_quads_41));
    const fem::Mesh& m = g.mesh;
    EXPECT_EQ(g.version, "4.1");
    ASSERT_EQ(m.type, fem::ElementType::quad4);
    // Tags 2..14 numbered densely in tag order; the unused node 99 dropped.
    ASSERT_EQ(m.n_nodes(), 6);
    ASSERT_EQ(m.n_elements(), 2);
    EXPECT_EQ(m.coordinate(0, 0), 0.0);
    EXPECT_EQ(m.coordinate(2, 0), 2.0);
    EXPECT_EQ(m.coordinate(5, 0), 2.0);
    EXPECT_EQ(m.coordinate(5, 1), 1.0);
    EXPECT_EQ(m.connectivity, (std::vector<int>{0, 1, 4, 3, 1, 2, 5, 4}));
    EXPECT_EQ(g.mirrored, 1);
    // Element sets by name, "group<tag>" without one, "all".
    EXPECT_EQ(m.element_set("left"), std::vector<int>{0});
    EXPECT_EQ(m.element_set("group2"), std::vector<int>{1});
    EXPECT_EQ(m.element_set("soil"), (std::vector<int>{0, 1}));
    EXPECT_EQ(m.element_set("all"), (std::vector<int>{0, 1}));
    EXPECT_EQ(m.element_sets.size(), 4u);
    // Face sets: each line is the local face of its quadrangle with the same nodes.
    EXPECT_EQ(m.face_set("bottom"), (std::vector<fem::FaceRef>{{0, 0}, {1, 0}}));
    EXPECT_EQ(m.face_set("top"), (std::vector<fem::FaceRef>{{0, 2}}));
    EXPECT_EQ(m.face_set("group13"), (std::vector<fem::FaceRef>{{1, 1}}));
    EXPECT_EQ(m.face_sets.size(), 3u);
    // Node sets of every group; the point in no group is ignored.
    EXPECT_EQ(m.node_set("bottom"), (std::vector<int>{0, 1, 2}));
    EXPECT_EQ(m.node_set("top"), (std::vector<int>{3, 4}));
    EXPECT_EQ(m.node_set("corner"), std::vector<int>{0});
    EXPECT_EQ(m.node_set("soil"), (std::vector<int>{0, 1, 2, 3, 4, 5}));
    EXPECT_EQ(m.node_set("all"), (std::vector<int>{0, 1, 2, 3, 4, 5}));
    EXPECT_EQ(m.node_sets.size(), 8u); // corner bottom top group13 left group2 soil all
    EXPECT_EQ(m.nodes_of_faces("bottom"), m.node_set("bottom"));
    for (int e = 0; e < 2; ++e) {
        EXPECT_NEAR(signed_area(m, e), 1.0, 1e-14) << e;
    }
}

// The same two squares in MSH 2.2: the left square is written once per physical group.
TEST(GmshReader, Reads2dMsh22AndMergesCopiesOfAnElement) {
    const std::string text = R"($MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
3
1 11 "bottom"
2 1 "left"
2 5 "soil"
$EndPhysicalNames
$Nodes
6
2 0 0 0
4 1 0 0
6 2 0 0
10 0 1 0
12 1 1 0
14 2 1 0
$EndNodes
$Elements
5
1 1 2 11 1 2 4
2 1 2 11 2 4 6
3 3 2 1 1 2 4 12 10
4 3 2 5 1 2 4 12 10
5 3 2 5 2 4 12 14 6
$EndElements
)";
    const GmshMesh g = read_gmsh_mesh(write_msh(text));
    const fem::Mesh& m = g.mesh;
    EXPECT_EQ(g.version, "2.2");
    ASSERT_EQ(m.n_elements(), 2);
    EXPECT_EQ(m.connectivity, (std::vector<int>{0, 1, 4, 3, 1, 2, 5, 4}));
    EXPECT_EQ(g.mirrored, 1);
    EXPECT_EQ(m.element_set("left"), std::vector<int>{0});
    EXPECT_EQ(m.element_set("soil"), (std::vector<int>{0, 1}));
    EXPECT_EQ(m.face_set("bottom"), (std::vector<fem::FaceRef>{{0, 0}, {1, 0}}));
    EXPECT_EQ(m.node_set("bottom"), (std::vector<int>{0, 1, 2}));
}

// Two unit cubes stacked along z; the upper one written upside down (inverted). Groups:
// volume "block" (both), quadrangles "base" (z = 0), "lid" (z = 2), line "edge" (y = z = 0).
std::string two_hexes_41(const std::string& extra_quads = "") {
    return R"($MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
4
1 4 "edge"
2 2 "base"
2 3 "lid"
3 1 "block"
$EndPhysicalNames
$Entities
0 1 3 1
1 0 0 0 1 0 0 1 4 0
1 0 0 0 1 1 0 1 2 0
2 0 0 2 1 1 2 1 3 0
3 0 0 1 1 1 1 1 9 0
1 0 0 0 1 1 2 1 1 0
$EndEntities
$Nodes
1 12 1 12
3 1 0 12
1
2
3
4
5
6
7
8
9
10
11
12
0 0 0
1 0 0
1 1 0
0 1 0
0 0 1
1 0 1
1 1 1
0 1 1
0 0 2
1 0 2
1 1 2
0 1 2
$EndNodes
$Elements
)" + std::string(extra_quads.empty() ? "4 5 1 5\n" : "5 6 1 6\n") +
           R"(1 1 1 1
1 1 2
2 1 3 1
2 4 3 2 1
2 2 3 1
3 9 10 11 12
3 1 5 2
4 1 2 3 4 5 6 7 8
5 9 10 11 12 5 6 7 8
)" + extra_quads +
           "$EndElements\n";
}

TEST(GmshReader, Reads3dHexahedraAndBoundaryQuadrangles) {
    const GmshMesh g = read_gmsh_mesh(write_msh(two_hexes_41()));
    const fem::Mesh& m = g.mesh;
    ASSERT_EQ(m.type, fem::ElementType::hex8);
    ASSERT_EQ(m.n_nodes(), 12);
    ASSERT_EQ(m.n_elements(), 2);
    EXPECT_EQ(m.coordinate(11, 2), 2.0);
    // The inverted hexahedron is mirrored: its zeta = -1 face is now z = 1.
    EXPECT_EQ(g.mirrored, 1);
    EXPECT_EQ(m.connectivity, (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7, 4, 5, 6, 7, 8, 9, 10, 11}));
    EXPECT_EQ(m.element_set("block"), (std::vector<int>{0, 1}));
    EXPECT_EQ(m.face_set("base"), (std::vector<fem::FaceRef>{{0, 0}}));
    EXPECT_EQ(m.face_set("lid"), (std::vector<fem::FaceRef>{{1, 1}}));
    EXPECT_EQ(m.node_set("lid"), (std::vector<int>{8, 9, 10, 11}));
    EXPECT_EQ(m.node_set("edge"), (std::vector<int>{0, 1})); // a line in 3D: nodes only
    EXPECT_FALSE(m.face_sets.contains("edge"));
    EXPECT_EQ(m.node_set("all").size(), 12u);
}

TEST(GmshReader, MissingFileIsAnError) {
    const std::string file = (test::fresh_dir("missing") / "none.msh").string();
    try {
        read_gmsh_mesh(file);
        FAIL() << "no error";
    } catch (const MeshFileError& e) {
        EXPECT_EQ(e.file(), file);
        EXPECT_NE(std::string(e.what()).find("cannot open"), std::string::npos) << e.what();
    }
}

// Gmsh writes the bounding box of an entity without geometry as +-DBL_MAX to 16 digits, which
// rounds past the largest double; the reader does not use bounding boxes and takes them.
TEST(GmshReader, UnboundedEntityBoundingBoxesAreRead) {
    const std::string text = replaced(two_quads_41, "1 0 0 0 1 0 0 1 11 0",
                                      "1 -1.797693134862316e+308 0 0 1.797693134862316e+308 0 0 "
                                      "1 11 0");
    const GmshMesh g = read_gmsh_mesh(write_msh(text));
    EXPECT_EQ(g.mesh.n_elements(), 2);
    expect_mesh_error(replaced(two_quads_41, "1 0 0 0 1 0 0 1 11 0", "1 x 0 0 1 0 0 1 11 0"), 16,
                      "bounding box");
}

TEST(GmshReader, TruncatedSectionNamesFileAndLine) {
    // The second node block is missing.
    const std::string cut = replaced(two_quads_41, "1 3 1 1\n99\n5 5 0 0.5\n", "");
    expect_mesh_error(cut, line_of(cut, "$EndNodes"),
                      "truncated $Nodes section: expected a node block's entity dimension, "
                      "found '$EndNodes'");
    // Elements end before the announced count.
    const std::string short_elements = replaced(two_quads_41, "7 4 12 14 6\n", "");
    expect_mesh_error(short_elements, line_of(short_elements, "$EndElements"),
                      "truncated $Elements section");
    // The file ends inside a section.
    const std::string ended = two_quads_41.substr(0, two_quads_41.find("12\n14\n"));
    expect_mesh_error(ended, line_of(ended, "10\n") + 1,
                      "truncated $Nodes section: expected a node tag, found the end of the file");
}

TEST(GmshReader, UnsupportedElementTypeNamesFileAndLine) {
    // A triangle among the quadrangles of a 2D mesh.
    const std::string text = replaced(two_quads_41, "8 8 7 100\n", "9 9 7 101\n") + "";
    const std::string with_triangle =
        replaced(text, "$EndElements", "2 2 2 1\n101 4 6 14\n$EndElements");
    expect_mesh_error(with_triangle, line_of(with_triangle, "101 4 6 14"),
                      "element 101 is a 3-node triangle (Gmsh type 2); a 2D mesh must consist "
                      "of 4-node quadrangles (type 3) only");
    // A 3-node line in a boundary group.
    const std::string curved = replaced(two_quads_41, "1 3 1 1\n62 12 10", "1 3 8 1\n62 12 10 4");
    expect_mesh_error(curved, line_of(curved, "62 12 10 4"), "3-node line (Gmsh type 8)");
    // A number that is no element type at all.
    const std::string unknown = replaced(two_quads_41, "1 3 1 1\n62 12 10", "1 3 77 1\n62 12 10");
    expect_mesh_error(unknown, line_of(unknown, "62 12 10"), "unknown Gmsh element type 77");
}

TEST(GmshReader, BoundaryElementWithoutParentIsAnError) {
    // The diagonal of the left square is no face of any quadrangle.
    const std::string diagonal = replaced(two_quads_41, "62 12 10", "62 2 12");
    expect_mesh_error(diagonal, line_of(diagonal, "62 2 12"),
                      "boundary element 62 of physical group \"top\" (nodes 2 12) is not a face "
                      "of any quadrangle");
    // The face between the two hexahedra has two of them: not on the boundary.
    const std::string middle = two_hexes_41("2 3 3 1\n6 5 6 7 8\n");
    expect_mesh_error(middle, line_of(middle, "6 5 6 7 8"), "is shared by 2 elements");
    // A boundary node that no quadrangle has.
    const std::string outside = replaced(two_quads_41, "62 12 10", "62 12 99");
    expect_mesh_error(outside, line_of(outside, "62 12 99"), "node 99, which belongs to no");
}

TEST(GmshReader, OtherBadFilesAreErrors) {
    expect_mesh_error(replaced(two_quads_41, "4.1 0 8", "4.1 1 8"), 0,
                      "says file type 1 (binary) but holds text");
    expect_mesh_error(replaced(two_quads_41, "4.1 0 8", "4 0 8"), 2, "version 4.1 or 2.2");
    expect_mesh_error("", 1, "starting with '$MeshFormat'");
    // 2D meshes lie in z = 0.
    const std::string lifted = replaced(two_quads_41, "2 1 0\n1 3 1 1", "2 1 0.5\n1 3 1 1");
    expect_mesh_error(lifted, line_of(lifted, "2 1 0.5"), "node 14 has z = 0.5");
    // A quadrangle with a repeated node.
    const std::string collapsed = replaced(two_quads_41, "100 2 4 12 10", "100 2 4 12 12");
    expect_mesh_error(collapsed, line_of(collapsed, "100 2 4 12 12"), "degenerate");
    // A node tag no $Nodes entry defines.
    const std::string unknown_node = replaced(two_quads_41, "100 2 4 12 10", "100 2 4 12 11");
    expect_mesh_error(unknown_node, line_of(unknown_node, "100 2 4 12 11"),
                      "names node 11, which $Nodes does not define");
    // Two groups of the same name.
    const std::string twice = replaced(two_quads_41, "1 12 \"top\"", "1 12 \"left\"");
    expect_mesh_error(twice, line_of(twice, "1 12 \"left\""), "both named \"left\"");
    // A bad number.
    const std::string word = replaced(two_quads_41, "0 1 0\n1 1 0", "0 one 0\n1 1 0");
    expect_mesh_error(word, line_of(word, "0 one 0"), "found 'one'");
}

} // namespace
} // namespace ifsim::io

namespace ifsim::io {
namespace {

// Binary MSH files (Gmsh's -bin; tests/io/mesh/data made by Debian 12's gmsh 4.8.4 from
// scenes/meshes/*.geo with -clscale 3 (2D) and 2 (3D), each in ASCII and binary from the same
// meshing): the binary file gives the ASCII file's mesh — the same sets and connectivity, the
// coordinates to the last digits Gmsh prints in ASCII — in 4.1 and 2.2, 2D and 3D.
void expect_same_mesh(const fem::Mesh& a, const fem::Mesh& b) {
    ASSERT_EQ(a.type, b.type);
    ASSERT_EQ(a.coordinates.size(), b.coordinates.size());
    for (std::size_t i = 0; i < a.coordinates.size(); ++i) {
        EXPECT_NEAR(a.coordinates[i], b.coordinates[i], 1e-15 * (1.0 + std::abs(a.coordinates[i])));
    }
    EXPECT_EQ(a.connectivity, b.connectivity);
    EXPECT_EQ(a.node_sets, b.node_sets);
    EXPECT_EQ(a.face_sets, b.face_sets);
    EXPECT_EQ(a.element_sets, b.element_sets);
}

TEST(GmshReader, BinaryFilesGiveTheAsciiMesh) {
    const std::string dir = "tests/io/mesh/data/";
    const GmshMesh ascii2 = read_gmsh_mesh(dir + "box2d-ascii-41.msh");
    EXPECT_GT(ascii2.mesh.n_elements(), 10);
    for (const char* f : {"box2d-binary-41.msh", "box2d-binary-22.msh"}) {
        const GmshMesh bin = read_gmsh_mesh(dir + f);
        SCOPED_TRACE(f);
        expect_same_mesh(bin.mesh, ascii2.mesh);
    }
    const GmshMesh ascii3 = read_gmsh_mesh(dir + "box3d-ascii-41.msh");
    const GmshMesh bin3 = read_gmsh_mesh(dir + "box3d-binary-41.msh");
    EXPECT_EQ(bin3.mesh.type, fem::ElementType::hex8);
    expect_same_mesh(bin3.mesh, ascii3.mesh);
}

TEST(GmshReader, DamagedBinaryFilesAreErrorsNamingTheFile) {
    std::ifstream in("tests/io/mesh/data/box2d-binary-41.msh", std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_GT(bytes.size(), 1000u);
    // Cut in the middle of the node coordinates.
    const std::string cut = bytes.substr(0, bytes.find("$EndNodes") - 100);
    expect_mesh_error(cut, 0, "binary mesh file: truncated");
    // A foreign byte order (the marker int 1 written big-endian).
    std::string swapped = bytes;
    const auto at = swapped.find("4.1 1 8\n") + 8;
    swapped.replace(at, 4, std::string("\0\0\0\1", 4));
    expect_mesh_error(swapped, 0, "byte order");
    // MSH 2.2: a count written as text that is no count, and raw bytes where a section ends
    // (shown escaped: the message goes into summary.json).
    std::ifstream in22("tests/io/mesh/data/box2d-binary-22.msh", std::ios::binary);
    const std::string b22((std::istreambuf_iterator<char>(in22)), std::istreambuf_iterator<char>());
    const auto nodes = b22.find("$Nodes\n") + 7;
    const std::string no_count = b22.substr(0, nodes) + "xx" + b22.substr(b22.find('\n', nodes));
    expect_mesh_error(no_count, 0, "expected the number of nodes (a count), found 'xx'");
    std::string raw = b22;
    raw.replace(raw.find("$EndNodes"), 2, "\xff\xfe");
    expect_mesh_error(raw, 0, "found '\\xff\\xfendNodes'");
}

} // namespace
} // namespace ifsim::io
