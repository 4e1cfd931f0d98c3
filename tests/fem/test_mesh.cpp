// Mesh, structured generators and their named sets, element geometry, unit loads, the DOF map
// (elimination, ties, conflicts) and the element colouring of the sparse system.
#include <gtest/gtest.h>

#include <set>

#include "fem/dof_map.hpp"
#include "fem/element_geometry.hpp"
#include "fem/loads.hpp"
#include "fem/sparse_system.hpp"
#include "tests/fem/fem_test_support.hpp"

using namespace ifsim;
using namespace ifsim::fem;
using namespace ifsim::fem::testing;

TEST(Mesh, RectangleSetsSitOnTheirSides) {
    const Mesh m = rectangle_mesh({2.0, 1.0, 4, 2, {1.0, -1.0}});
    EXPECT_EQ(m.n_nodes(), 15);
    EXPECT_EQ(m.n_elements(), 8);
    EXPECT_NO_THROW(m.validate());
    const std::pair<const char*, std::pair<int, double>> sides[] = {
        {"left", {0, 1.0}}, {"right", {0, 3.0}}, {"bottom", {1, -1.0}}, {"top", {1, 0.0}}};
    for (const auto& [name, where] : sides) {
        for (int n : m.node_set(name)) {
            EXPECT_DOUBLE_EQ(m.coordinate(n, where.first), where.second) << name;
        }
        auto sorted_nodes = m.node_set(name);
        std::sort(sorted_nodes.begin(), sorted_nodes.end());
        EXPECT_EQ(m.nodes_of_faces(name), sorted_nodes) << name;
    }
    EXPECT_EQ(m.node_set("left").size(), 3u);
    EXPECT_EQ(m.face_set("top").size(), 4u);
    EXPECT_THROW(m.node_set("front"), std::out_of_range);
}

TEST(Mesh, BoxSetsAndFaceNormalsPointOutwards) {
    const Mesh m = box_mesh({1.0, 2.0, 3.0, 2, 3, 4});
    EXPECT_EQ(m.n_nodes(), 3 * 4 * 5);
    EXPECT_EQ(m.n_elements(), 24);
    // A unit pressure pushes inwards: the forces sum to -n A on each face set.
    const std::pair<const char*, std::array<double, 3>> faces[] = {
        {"left", {-1, 0, 0}}, {"right", {1, 0, 0}},   {"front", {0, -1, 0}},
        {"back", {0, 1, 0}},  {"bottom", {0, 0, -1}}, {"top", {0, 0, 1}}};
    const std::array<double, 3> size = {1.0, 2.0, 3.0};
    for (const auto& [name, n] : faces) {
        const auto f = unit_pressure_forces(m, name);
        double area = 1.0;
        for (int i = 0; i < 3; ++i) {
            area *= n[static_cast<std::size_t>(i)] != 0.0 ? 1.0 : size[static_cast<std::size_t>(i)];
        }
        for (int i = 0; i < 3; ++i) {
            double sum = 0.0;
            for (int node = 0; node < m.n_nodes(); ++node) {
                sum += f[static_cast<std::size_t>(node * 3 + i)];
            }
            EXPECT_NEAR(sum, -n[static_cast<std::size_t>(i)] * area, 1e-12) << name << " " << i;
        }
    }
}

TEST(Mesh, QuadEdgeNormalsPointOutwards) {
    Mesh m = rectangle_mesh({2.0, 1.0, 2, 2});
    distort(m, 0.1, 0.5); // the boundary is no longer straight: forces still sum to -n L
    for (const char* name : {"left", "right", "bottom", "top"}) {
        const auto f = unit_pressure_forces(m, name);
        double fx = 0.0, fy = 0.0;
        for (int node = 0; node < m.n_nodes(); ++node) {
            fx += f[static_cast<std::size_t>(node * 2)];
            fy += f[static_cast<std::size_t>(node * 2 + 1)];
        }
        // Closed form: -sum over edges of (t_y, -t_x) = -(y_end - y_start, x_start - x_end).
        const auto& faces = m.face_set(name);
        double ex = 0.0, ey = 0.0;
        for (const FaceRef& fr : faces) {
            const auto loc = face_nodes(m.type, fr.local_face);
            const int a = m.node(fr.element, loc[0]);
            const int b = m.node(fr.element, loc[1]);
            ex -= m.coordinate(b, 1) - m.coordinate(a, 1);
            ey -= m.coordinate(a, 0) - m.coordinate(b, 0);
        }
        EXPECT_NEAR(fx, ex, 1e-14) << name;
        EXPECT_NEAR(fy, ey, 1e-14) << name;
        const std::string s = name;
        if (s == "left") {
            EXPECT_GT(fx, 0.9); // pushes to +x
        }
        if (s == "top") {
            EXPECT_LT(fy, -1.9); // pushes down
        }
    }
}

TEST(ElementGeometry, VolumesAndReducedGradients) {
    Mesh m = box_mesh({1.0, 2.0, 3.0, 2, 2, 2});
    const auto full = build_geometry(m, Integration::full);
    double V = 0.0;
    for (double w : full.dV) {
        V += w;
    }
    EXPECT_NEAR(V, 6.0, 1e-12);
    distort(m, 0.15, 0.5);
    const auto f2 = build_geometry(m, Integration::full);
    const auto r2 = build_geometry(m, Integration::reduced);
    EXPECT_EQ(r2.nip, 1);
    for (int e = 0; e < m.n_elements(); ++e) {
        double v = 0.0;
        for (int q = 0; q < 8; ++q) {
            v += f2.weight(e, q);
        }
        EXPECT_NEAR(r2.weight(e, 0), v, 1e-14);
        // The uniform gradients are the volume average of the Gauss-point gradients.
        for (int k = 0; k < 24; ++k) {
            double avg = 0.0;
            for (int q = 0; q < 8; ++q) {
                avg += f2.gradients(e, q)[k] * f2.weight(e, q);
            }
            EXPECT_NEAR(r2.gradients(e, 0)[k], avg / v, 1e-12);
        }
    }
}

TEST(ElementGeometry, InvertedElementIsRejected) {
    Mesh m = rectangle_mesh({1.0, 1.0, 1, 1});
    std::swap(m.connectivity[1], m.connectivity[3]); // clockwise
    EXPECT_THROW(build_geometry(m, Integration::full), std::invalid_argument);
}

TEST(DofMap, EliminationTiesAndConflicts) {
    Mesh m = rectangle_mesh({1.0, 1.0, 2, 2});
    Stage st;
    st.displacements = {{"bottom", 0, 0.0}, {"bottom", 1, 0.0}, {"left", 0, 0.0}};
    st.equal_displacements = {{"top", 1}};
    const DofMap d = build_dof_map(m, st);
    // 9 nodes, 18 DOFs; 3 bottom nodes x 2 + 2 more left x = 8 prescribed; top y: 3 DOFs, 1 eq.
    EXPECT_EQ(d.prescribed.size(), 8u);
    EXPECT_EQ(d.n_equations, 18 - 8 - 2);
    const auto& top = m.node_set("top");
    for (int n : top) {
        EXPECT_EQ(d.equation[static_cast<std::size_t>(n * 2 + 1)],
                  d.equation[static_cast<std::size_t>(top.front() * 2 + 1)]);
    }
    Stage clash = st;
    clash.displacements.push_back({"left", 0, 1e-3}); // same DOFs, other value
    EXPECT_THROW(build_dof_map(m, clash), std::invalid_argument);
    Stage tied_and_fixed = st;
    tied_and_fixed.equal_displacements.push_back({"left", 0});
    EXPECT_THROW(build_dof_map(m, tied_and_fixed), std::invalid_argument);
    Stage twice = st;
    twice.equal_displacements.push_back({"right", 1}); // top-right node is in both ties
    EXPECT_THROW(build_dof_map(m, twice), std::invalid_argument);
    Stage bad_dir = st;
    bad_dir.displacements.push_back({"top", 2, 0.0});
    EXPECT_THROW(build_dof_map(m, bad_dir), std::invalid_argument);
}

TEST(SparseSystem, ColoursNeverShareANodeOrAnEquation) {
    Mesh m = box_mesh({1.0, 1.0, 1.0, 4, 3, 3});
    Stage st;
    st.displacements = {{"bottom", 2, 0.0}, {"left", 0, 0.0}, {"front", 1, 0.0}};
    st.equal_displacements = {{"top", 2}};
    const DofMap d = build_dof_map(m, st);
    const SparseSystem sys(m, d);
    int total = 0;
    for (int c = 0; c < sys.n_colours(); ++c) {
        std::set<int> nodes, eqs;
        for (int e : sys.colour(c)) {
            ++total;
            for (int a = 0; a < 8; ++a) {
                EXPECT_TRUE(nodes.insert(m.node(e, a)).second) << "colour " << c;
            }
            std::set<int> own;
            for (int q : sys.element_equations(e)) {
                if (q >= 0) {
                    own.insert(q);
                }
            }
            for (int q : own) {
                EXPECT_TRUE(eqs.insert(q).second) << "colour " << c;
            }
        }
    }
    EXPECT_EQ(total, m.n_elements());
    EXPECT_GE(sys.n_colours(), 8);
    // Every element's entries exist in the pattern: the matrix is n_eq square.
    EXPECT_EQ(sys.n_equations(), d.n_equations);
    EXPECT_EQ(sys.matrix().rows(), d.n_equations);
}
