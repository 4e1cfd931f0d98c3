// Projection of points onto a 2D master surface (Eqs. A9-A13): straight, kinked and curved
// polylines, continuation across edges, natural borders, gaps.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "fem/mortar_surface_2d.hpp"

namespace {

using namespace ifsim::fem;

// A row of quad4 elements under the polyline (x_i, y_i) (x increasing); face set "top".
Mesh body_below(const std::vector<std::array<double, 2>>& top) {
    Mesh m;
    m.type = ElementType::quad4;
    const int n = static_cast<int>(top.size());
    for (const auto& p : top) { // bottom nodes 0..n-1, top nodes n..2n-1
        m.coordinates.insert(m.coordinates.end(), {p[0], -5.0});
    }
    for (const auto& p : top) {
        m.coordinates.insert(m.coordinates.end(), {p[0], p[1]});
    }
    for (int i = 0; i + 1 < n; ++i) {
        m.connectivity.insert(m.connectivity.end(), {i, i + 1, n + i + 1, n + i});
        m.face_sets["top"].push_back({i, 2});
    }
    m.validate();
    return m;
}

TEST(MortarProjection, StraightMasterAcrossEdgesAndGaps) {
    const Mesh m = body_below({{0, 0}, {1, 0}, {2, 0}, {3, 0}});
    MortarSurface2D s(m, "top");
    ASSERT_EQ(s.n_edges(), 3);
    for (int start = -1; start < 3; ++start) { // any start edge walks to the same point
        const auto p = s.project({1.3, 0.2}, start);
        ASSERT_TRUE(p.in_contact);
        EXPECT_NEAR(p.x[0], 1.3, 1e-13);
        EXPECT_NEAR(p.x[1], 0.0, 1e-13);
        EXPECT_NEAR(p.normal[0], 0.0, 1e-14);
        EXPECT_NEAR(p.normal[1], 1.0, 1e-14); // out of the master, towards the slave
        EXPECT_NEAR(normal_gap(p, {1.3, 0.2}), 0.2, 1e-13);
        EXPECT_NEAR(p.N[0] * m.coordinate(p.nodes[0], 0) + p.N[1] * m.coordinate(p.nodes[1], 0),
                    1.3, 1e-13);
    }
    // Penetration: negative normal gap (Eq. 7 sign).
    EXPECT_NEAR(normal_gap(s.project({2.5, -0.1}), {2.5, -0.1}), -0.1, 1e-13);
    // A point above a node projects onto it.
    const auto at_node = s.project({2.0, 0.3});
    ASSERT_TRUE(at_node.in_contact);
    EXPECT_NEAR(at_node.x[0], 2.0, 1e-13);
}

TEST(MortarProjection, NaturalBorders) {
    const Mesh m = body_below({{0, 0}, {1, 0}, {2, 0}});
    MortarSurface2D s(m, "top");
    EXPECT_FALSE(s.project({2.3, 0.1}).in_contact);
    EXPECT_FALSE(s.project({-0.01, 0.1}).in_contact);
    EXPECT_FALSE(s.project({2.3, 0.1}, 0).in_contact); // walking from the far edge
    const auto end = s.project({2.0, 0.1});
    ASSERT_TRUE(end.in_contact);
    EXPECT_NEAR(end.x[0], 2.0, 1e-13);
    EXPECT_TRUE(s.project({1e-9, 0.1}).in_contact);
}

TEST(MortarProjection, ConvexKinkIsSmoothed) {
    // A peak at (1, 1): without smoothing a point above the peak has no orthogonal
    // projection onto either edge; the averaged nodal tangent is horizontal there.
    const Mesh m = body_below({{0, 0}, {1, 1}, {2, 0}});
    MortarSurface2D s(m, "top");
    const auto p = s.project({1.0, 2.0});
    ASSERT_TRUE(p.in_contact);
    EXPECT_NEAR(p.x[0], 1.0, 1e-12);
    EXPECT_NEAR(p.x[1], 1.0, 1e-12);
    EXPECT_NEAR(p.normal[1], 1.0, 1e-12);
    EXPECT_NEAR(normal_gap(p, {1.0, 2.0}), 1.0, 1e-12);
    // Moving the point across the peak moves the projection continuously over the node.
    const auto l = s.project({1.0 - 1e-4, 2.0});
    const auto r = s.project({1.0 + 1e-4, 2.0});
    ASSERT_TRUE(l.in_contact && r.in_contact);
    EXPECT_NE(l.edge, r.edge);
    EXPECT_LT(l.x[0], 1.0);
    EXPECT_GT(r.x[0], 1.0);
    EXPECT_NEAR(l.x[0], 1.0, 1e-3);
    EXPECT_NEAR(r.x[0], 1.0, 1e-3);
    // Away from the kink: x - p is along the smoothed normal (Eq. A9 with the smoothed
    // tangent), and the smoothed normal tilts towards the peak's horizontal normal.
    const std::array<double, 2> q{-0.5, 1.5};
    const auto mid = s.project(q);
    ASSERT_TRUE(mid.in_contact);
    EXPECT_NEAR((q[0] - mid.x[0]) * mid.tangent[0] + (q[1] - mid.x[1]) * mid.tangent[1], 0.0,
                1e-12);
    EXPECT_NEAR(mid.x[0], mid.x[1], 1e-14); // on the edge y = x
    EXPECT_GT(mid.normal[1], std::sqrt(0.5));
    EXPECT_LT(mid.normal[1], 1.0);
}

TEST(MortarProjection, ConcaveKinkProjectsOntoNode) {
    const Mesh m = body_below({{0, 1}, {1, 0}, {2, 1}});
    MortarSurface2D s(m, "top");
    for (int start = -1; start < 2; ++start) {
        const auto p = s.project({1.0, 0.5}, start);
        ASSERT_TRUE(p.in_contact);
        EXPECT_NEAR(p.x[0], 1.0, 1e-12);
        EXPECT_NEAR(p.x[1], 0.0, 1e-12);
        EXPECT_NEAR(normal_gap(p, {1.0, 0.5}), 0.5, 1e-12);
    }
}

TEST(MortarProjection, CurvedPolylineBySymmetry) {
    // Regular polygon on a circle of radius 1: a point on the ray through a node projects
    // onto the node, a point on the ray through an edge midpoint onto the midpoint.
    const double pi = std::numbers::pi;
    const int n = 12;
    const double a0 = 150.0 * pi / 180.0;
    const double da = -120.0 * pi / 180.0 / n;
    std::vector<std::array<double, 2>> top;
    for (int i = 0; i <= n; ++i) {
        top.push_back({std::cos(a0 + i * da), std::sin(a0 + i * da)});
    }
    const Mesh m = body_below(top);
    MortarSurface2D s(m, "top");
    for (int i = 1; i < n; ++i) {
        const double a = a0 + i * da;
        const auto p = s.project({1.5 * std::cos(a), 1.5 * std::sin(a)}, 0);
        ASSERT_TRUE(p.in_contact);
        EXPECT_NEAR(p.x[0], std::cos(a), 1e-12);
        EXPECT_NEAR(p.x[1], std::sin(a), 1e-12);
        EXPECT_NEAR(p.normal[0], std::cos(a), 1e-12);
        if (i + 1 == n) {
            continue; // the last edge's end tangent is its own (chain end): not symmetric
        }
        const double am = a + 0.5 * da;
        const double c = std::cos(0.5 * da);
        const std::array<double, 2> q{0.7 * std::cos(am), 0.7 * std::sin(am)}; // penetrating
        const auto pm = s.project(q, n - 1);
        ASSERT_TRUE(pm.in_contact);
        EXPECT_NEAR(pm.xi, 0.0, 1e-12);
        EXPECT_NEAR(normal_gap(pm, q), 0.7 - c, 1e-12);
        EXPECT_LE(pm.iterations, 3 * n);
    }
}

TEST(MortarProjection, DisplacedConfigurationAndTangentialIncrement) {
    const Mesh m = body_below({{0, 0}, {1, 0}, {2, 0}});
    MortarSurface2D s(m, "top");
    // Displaced: the master surface lifted by 0.1 and shifted right by 0.05.
    std::vector<double> u(m.coordinates.size(), 0.0);
    for (int a = 0; a < m.n_nodes(); ++a) {
        u[static_cast<std::size_t>(2 * a)] = 0.05;
        u[static_cast<std::size_t>(2 * a + 1)] = 0.1;
    }
    s.set_configuration(m, &u);
    const auto p = s.project({0.55, 0.3});
    ASSERT_TRUE(p.in_contact);
    EXPECT_NEAR(p.x[0], 0.55, 1e-13);
    EXPECT_NEAR(normal_gap(p, {0.55, 0.3}), 0.2, 1e-13);
    // Eq. A13: the tangent runs along the edges (right to left for a top face), the increment
    // is master minus slave motion along it.
    EXPECT_NEAR(p.tangent[0], -1.0, 1e-14);
    EXPECT_NEAR(tangential_gap_increment(p, u, {0.02, 0.0}), -(0.05 - 0.02), 1e-14);
    // Slave integration points: 2 per edge, weights sum to the length.
    double length = 0.0;
    for (const auto& g : s.integration_points()) {
        length += g.weight_j;
    }
    EXPECT_NEAR(length, 2.0, 1e-14);
}

} // namespace
