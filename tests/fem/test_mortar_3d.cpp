// 3D mortar contact on hex8 meshes (Eqs. A11-A21): projection onto flat, kinked and curved
// master surfaces with continuation across faces and free borders, the local frame, slave
// integration points; forces against the consistent pressure loads, the tangent against
// finite differences, the elastic patch test, a block sliding over several master faces.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <numbers>
#include <random>
#include <set>

#include <Eigen/Dense>

#include "fem/element_kernels.hpp"
#include "fem/mortar_contact.hpp"
#include "fem/shape_functions.hpp"
#include "fem/structured_mesh.hpp"

namespace {

using namespace ifsim::fem;

double dot3(const Vec3& a, const Vec3& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
Vec3 cross3(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

void expect_frame(const SurfaceProjection3D& p) {
    EXPECT_NEAR(dot3(p.normal, p.normal), 1.0, 1e-14);
    EXPECT_NEAR(dot3(p.t1, p.t1), 1.0, 1e-14);
    EXPECT_NEAR(dot3(p.t2, p.t2), 1.0, 1e-14);
    EXPECT_NEAR(dot3(p.normal, p.t1), 0.0, 1e-14);
    EXPECT_NEAR(dot3(p.normal, p.t2), 0.0, 1e-14);
    EXPECT_NEAR(dot3(p.t1, p.t2), 0.0, 1e-14);
    EXPECT_NEAR(dot3(p.normal, cross3(p.t1, p.t2)), 1.0, 1e-14); // right-handed (n, t1, t2)
}

// Master position sum N_J x_J of a projection, from the reference mesh.
Vec3 interpolate(const Mesh& m, const SurfaceProjection3D& p) {
    Vec3 x{};
    for (std::size_t c = 0; c < 4; ++c) {
        for (int d = 0; d < 3; ++d) {
            x[static_cast<std::size_t>(d)] += p.N[c] * m.coordinate(p.nodes[c], d);
        }
    }
    return x;
}

// One layer of hex8 elements under the height field z = h(x, y) on the grid xs x ys, bottom at
// z = -2; face set "top" (local face 1, outward +z).
Mesh body_below(const std::vector<double>& xs, const std::vector<double>& ys,
                const std::function<double(double, double)>& h) {
    Mesh m;
    m.type = ElementType::hex8;
    const int nx = static_cast<int>(xs.size());
    const int ny = static_cast<int>(ys.size());
    for (int layer = 0; layer < 2; ++layer) {
        for (double y : ys) {
            for (double x : xs) {
                m.coordinates.insert(m.coordinates.end(), {x, y, layer == 0 ? -2.0 : h(x, y)});
            }
        }
    }
    const auto id = [&](int i, int j, int layer) { return i + nx * (j + ny * layer); };
    for (int j = 0; j + 1 < ny; ++j) {
        for (int i = 0; i + 1 < nx; ++i) {
            m.connectivity.insert(m.connectivity.end(),
                                  {id(i, j, 0), id(i + 1, j, 0), id(i + 1, j + 1, 0),
                                   id(i, j + 1, 0), id(i, j, 1), id(i + 1, j, 1),
                                   id(i + 1, j + 1, 1), id(i, j + 1, 1)});
            m.face_sets["top"].push_back({m.n_elements() - 1, 1});
        }
    }
    m.validate();
    return m;
}

TEST(MortarSurface3D, FlatProjectionFromAnyStartFace) {
    const Mesh m = box_mesh({3.0, 2.0, 1.0, 3, 2, 1, {0.0, 0.0, -1.0}});
    MortarSurface3D s(m, "top");
    ASSERT_EQ(s.n_faces(), 6);
    // Inside a face, above a node, above an edge, penetrating.
    const std::vector<Vec3> pts{
        {1.3, 0.7, 0.2}, {1.0, 1.0, 0.3}, {2.0, 0.5, 0.1}, {1.5, 1.0, -0.1}, {0.25, 1.75, 0.4}};
    for (const Vec3& q : pts) {
        for (int start = -1; start < s.n_faces(); ++start) {
            const auto p = s.project(q, start);
            ASSERT_TRUE(p.in_contact) << "start " << start;
            EXPECT_NEAR(p.x[0], q[0], 1e-13);
            EXPECT_NEAR(p.x[1], q[1], 1e-13);
            EXPECT_NEAR(p.x[2], 0.0, 1e-13);
            const Vec3 xi = interpolate(m, p);
            for (std::size_t d = 0; d < 3; ++d) {
                EXPECT_NEAR(xi[d], p.x[d], 1e-13);
            }
            EXPECT_NEAR(p.normal[2], 1.0, 1e-14); // out of the master, towards the slave
            EXPECT_NEAR(normal_gap(p, q), q[2], 1e-13);
            // t1 along the face's xi1 (+x for a top face), t2 = n x t1 = +y.
            EXPECT_NEAR(p.t1[0], 1.0, 1e-14);
            EXPECT_NEAR(p.t2[1], 1.0, 1e-14);
            expect_frame(p);
            EXPECT_LE(std::max(std::abs(p.xi[0]), std::abs(p.xi[1])), 1.0);
            EXPECT_LE(p.iterations, 20);
        }
    }
}

TEST(MortarSurface3D, FreeBorderAndCorners) {
    const Mesh m = box_mesh({3.0, 2.0, 1.0, 3, 2, 1, {0.0, 0.0, -1.0}});
    MortarSurface3D s(m, "top");
    for (int start = -1; start < s.n_faces(); ++start) {
        EXPECT_FALSE(s.project({3.1, 1.0, 0.1}, start).in_contact);
        EXPECT_FALSE(s.project({1.5, -0.01, 0.1}, start).in_contact);
        EXPECT_FALSE(s.project({3.01, 2.01, 0.1}, start).in_contact); // beyond a corner
        EXPECT_FALSE(s.project({-0.2, 2.5, -0.1}, start).in_contact);
        const auto border = s.project({3.0, 1.3, 0.1}, start); // on the border
        ASSERT_TRUE(border.in_contact);
        EXPECT_NEAR(border.x[0], 3.0, 1e-13);
        EXPECT_NEAR(border.x[1], 1.3, 1e-13);
        const auto corner = s.project({3.0, 2.0, 0.1}, start);
        ASSERT_TRUE(corner.in_contact);
        EXPECT_NEAR(corner.x[0], 3.0, 1e-13);
        EXPECT_NEAR(corner.x[1], 2.0, 1e-13);
        EXPECT_TRUE(s.project({1e-9, 1e-9, 0.1}, start).in_contact);
    }
}

TEST(MortarSurface3D, RidgeIsSmoothed) {
    // A roof z = 1 - |x - 1|: without smoothing a point above the ridge has no orthogonal
    // projection onto either slope; the averaged nodal normal is vertical on the ridge.
    const Mesh m =
        body_below({0, 1, 2}, {0, 1, 2}, [](double x, double) { return 1.0 - std::abs(x - 1.0); });
    MortarSurface3D s(m, "top");
    for (int start = -1; start < s.n_faces(); ++start) {
        for (const double y : {0.6, 1.0, 2.0}) { // above the edge, a ridge node, a border node
            const auto p = s.project({1.0, y, 2.0}, start);
            ASSERT_TRUE(p.in_contact);
            EXPECT_NEAR(p.x[0], 1.0, 1e-12);
            EXPECT_NEAR(p.x[1], y, 1e-12);
            EXPECT_NEAR(p.x[2], 1.0, 1e-12);
            EXPECT_NEAR(p.normal[2], 1.0, 1e-12);
            EXPECT_NEAR(normal_gap(p, {1.0, y, 2.0}), 1.0, 1e-12);
            expect_frame(p);
        }
    }
    // Crossing the ridge moves the projection continuously over it, onto different faces.
    const auto l = s.project({1.0 - 1e-4, 0.6, 2.0});
    const auto r = s.project({1.0 + 1e-4, 0.6, 2.0});
    ASSERT_TRUE(l.in_contact && r.in_contact);
    EXPECT_NE(l.face, r.face);
    EXPECT_LT(l.x[0], 1.0);
    EXPECT_GT(r.x[0], 1.0);
    EXPECT_NEAR(l.x[0], 1.0, 1e-3);
    EXPECT_NEAR(r.x[0], 1.0, 1e-3);
    // The smoothed normal is continuous across the ridge edge (shared nodal normals).
    for (int f = 0; f < s.n_faces(); ++f) {
        for (int k = 0; k < 4; ++k) {
            const int g = s.neighbour(f, k);
            if (g < 0) {
                continue;
            }
            // The midpoint of edge k in both faces' coordinates.
            const std::array<std::array<double, 2>, 4> mid{{{0, -1}, {1, 0}, {0, 1}, {-1, 0}}};
            const auto a = s.smoothed_normal(f, mid[static_cast<std::size_t>(k)]);
            int kb = 0;
            while (s.neighbour(g, kb) != f) {
                ++kb;
            }
            const auto b = s.smoothed_normal(g, mid[static_cast<std::size_t>(kb)]);
            for (std::size_t d = 0; d < 3; ++d) {
                EXPECT_NEAR(a[d], b[d], 1e-14);
            }
        }
    }
    // On a slope, x - p is along the smoothed normal (Eqs. A15, A16 with the smoothed normal),
    // which tilts from the slope's normal towards the vertical ridge normal.
    const Vec3 q{0.4, 0.6, 1.0};
    const auto p = s.project(q);
    ASSERT_TRUE(p.in_contact);
    const Vec3 g{q[0] - p.x[0], q[1] - p.x[1], q[2] - p.x[2]};
    const Vec3 c = cross3(g, p.normal);
    EXPECT_NEAR(std::sqrt(dot3(c, c)), 0.0, 1e-12);
    EXPECT_NEAR(p.x[2], p.x[0], 1e-14); // on the slope z = x
    EXPECT_NEAR(p.x[1], 0.6, 1e-14);
    EXPECT_GT(p.normal[2], std::sqrt(0.5));
    EXPECT_LT(p.normal[2], 1.0);
    expect_frame(p);
}

TEST(MortarSurface3D, PeakAndValleyProjectOntoNodeAndEdge) {
    // Peak: four non-planar faces meet at (1, 1, 1); a point above it projects onto the node.
    const Mesh peak = body_below(
        {0, 1, 2}, {0, 1, 2}, [](double x, double y) { return x == 1.0 && y == 1.0 ? 1.0 : 0.0; });
    MortarSurface3D s(peak, "top");
    for (int start = -1; start < s.n_faces(); ++start) {
        const auto p = s.project({1.0, 1.0, 3.0}, start);
        ASSERT_TRUE(p.in_contact);
        EXPECT_NEAR(p.x[0], 1.0, 1e-12);
        EXPECT_NEAR(p.x[1], 1.0, 1e-12);
        EXPECT_NEAR(p.x[2], 1.0, 1e-12);
        EXPECT_NEAR(normal_gap(p, {1.0, 1.0, 3.0}), 2.0, 1e-12);
        expect_frame(p);
    }
    // Concave valley z = |x - 1|: above (and below) the valley edge onto the edge.
    const Mesh valley =
        body_below({0, 1, 2}, {0, 1, 2}, [](double x, double) { return std::abs(x - 1.0); });
    MortarSurface3D v(valley, "top");
    for (int start = -1; start < v.n_faces(); ++start) {
        for (const double z : {0.5, -0.2}) {
            const auto p = v.project({1.0, 0.6, z}, start);
            ASSERT_TRUE(p.in_contact);
            EXPECT_NEAR(p.x[0], 1.0, 1e-12);
            EXPECT_NEAR(p.x[1], 0.6, 1e-12);
            EXPECT_NEAR(p.x[2], 0.0, 1e-12);
            EXPECT_NEAR(normal_gap(p, {1.0, 0.6, z}), z, 1e-12);
        }
    }
}

TEST(MortarSurface3D, CylinderBySymmetryAcrossManyFaces) {
    // Quarter-and-more of a cylinder of radius 1 about the y axis (12 faces around, 3 along
    // y). A point on the ray through a node line projects onto the node with the radial
    // normal; a point on the ray through a face centre onto the centre (xi = 0), walking there
    // from the far end.
    const double pi = std::numbers::pi;
    const int n = 12;
    const double a0 = 150.0 * pi / 180.0;
    const double da = -120.0 * pi / 180.0 / n; // xi1 along -e_theta: outward x_xi1 x x_xi2
    const std::vector<double> ys{0.0, 0.5, 1.0, 1.5};
    const int na = n + 1;
    const int ny = static_cast<int>(ys.size());
    Mesh m;
    m.type = ElementType::hex8;
    for (const double r : {0.5, 1.0}) {
        for (double y : ys) {
            for (int i = 0; i < na; ++i) {
                const double a = a0 + i * da;
                m.coordinates.insert(m.coordinates.end(), {r * std::cos(a), y, r * std::sin(a)});
            }
        }
    }
    const auto id = [&](int i, int j, int layer) { return i + na * (j + ny * layer); };
    for (int j = 0; j + 1 < ny; ++j) {
        for (int i = 0; i < n; ++i) {
            m.connectivity.insert(m.connectivity.end(),
                                  {id(i, j, 0), id(i + 1, j, 0), id(i + 1, j + 1, 0),
                                   id(i, j + 1, 0), id(i, j, 1), id(i + 1, j, 1),
                                   id(i + 1, j + 1, 1), id(i, j + 1, 1)});
            m.face_sets["outer"].push_back({m.n_elements() - 1, 1});
        }
    }
    m.validate();
    MortarSurface3D s(m, "outer");
    for (int i = 1; i < n; ++i) {
        const double a = a0 + i * da;
        for (const double y : {0.5, 1.0}) {
            const Vec3 q{1.5 * std::cos(a), y, 1.5 * std::sin(a)};
            const auto p = s.project(q, 0);
            ASSERT_TRUE(p.in_contact);
            EXPECT_NEAR(p.x[0], std::cos(a), 1e-12);
            EXPECT_NEAR(p.x[1], y, 1e-12);
            EXPECT_NEAR(p.x[2], std::sin(a), 1e-12);
            EXPECT_NEAR(p.normal[0], std::cos(a), 1e-12);
            EXPECT_NEAR(p.normal[2], std::sin(a), 1e-12);
            EXPECT_NEAR(normal_gap(p, q), 0.5, 1e-12);
            expect_frame(p);
        }
        if (i + 1 == n) {
            continue; // the last face's end normal is its own (free border): not symmetric
        }
        const double am = a + 0.5 * da;
        const double c = std::cos(0.5 * da);
        for (const double y : {0.25, 0.75, 1.25}) {
            const Vec3 q{0.7 * std::cos(am), y, 0.7 * std::sin(am)}; // penetrating
            const int far = 3 * n - 1;                               // the other end
            const auto p = s.project(q, far);
            ASSERT_TRUE(p.in_contact);
            EXPECT_NEAR(p.xi[0], 0.0, 1e-12);
            EXPECT_NEAR(p.xi[1], 0.0, 1e-12);
            EXPECT_NEAR(normal_gap(p, q), 0.7 - c, 1e-12);
            EXPECT_LE(p.iterations, 6 * n);
        }
    }
}

TEST(MortarSurface3D, WavySurfaceSameProjectionFromEveryStartFace) {
    // Non-planar bilinear faces with kinks between them: for points near the surface the
    // projection is unique, so every start face walks to the same point, where x - p lies
    // along the smoothed normal (Eqs. A15, A16).
    Mesh m = box_mesh({3.0, 2.0, 1.0, 6, 4, 1, {0.0, 0.0, -1.0}});
    for (int a : m.node_set("top")) {
        m.coordinates[static_cast<std::size_t>(3 * a + 2)] +=
            0.08 * std::sin(2.1 * m.coordinate(a, 0) + 1.3 * m.coordinate(a, 1)) +
            0.05 * std::cos(5.0 * m.coordinate(a, 1));
    }
    MortarSurface3D s(m, "top");
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> ux(0.02, 2.98), uy(0.02, 1.98), uz(-0.3, 0.3);
    for (int k = 0; k < 40; ++k) {
        const Vec3 q{ux(rng), uy(rng), uz(rng)};
        const auto ref = s.project(q);
        ASSERT_TRUE(ref.in_contact);
        for (int start = 0; start < s.n_faces(); ++start) {
            const auto p = s.project(q, start);
            ASSERT_TRUE(p.in_contact);
            const Vec3 g{q[0] - p.x[0], q[1] - p.x[1], q[2] - p.x[2]};
            const Vec3 c = cross3(g, p.normal);
            EXPECT_LT(std::sqrt(dot3(c, c)), 1e-12);
            for (std::size_t d = 0; d < 3; ++d) {
                EXPECT_NEAR(p.x[d], ref.x[d], 1e-12);
            }
            EXPECT_NEAR(normal_gap(p, q), dot3(g, p.normal), 1e-15);
            expect_frame(p);
            EXPECT_LE(p.iterations, 40);
        }
    }
}

TEST(MortarSurface3D, SlaveIntegrationPointsAndDisplacedConfiguration) {
    Mesh m = box_mesh({2.0, 3.0, 1.0, 2, 3, 2});
    {
        MortarSurface3D s(m, "bottom");
        double area = 0.0;
        for (const auto& g : s.integration_points()) {
            area += g.weight_j;
        }
        EXPECT_NEAR(area, 6.0, 1e-13);
    }
    // Distorted mesh: each Gauss point's natural coordinates in its hex8 element map to the
    // point itself, on the element's face (one natural coordinate +-1).
    for (std::size_t i = 0; i < m.coordinates.size(); ++i) {
        m.coordinates[i] += 0.08 * std::sin(1.7 * static_cast<double>(i));
    }
    for (const char* set : {"bottom", "top", "left", "right", "front", "back"}) {
        MortarSurface3D s(m, set);
        for (const auto& g : s.integration_points()) {
            double N[8];
            Shape<ElementType::hex8>::values(g.natural.data(), N);
            const int e = s.face_ref(g.face).element;
            for (int d = 0; d < 3; ++d) {
                double x = 0.0;
                for (int a = 0; a < 8; ++a) {
                    x += N[a] * m.coordinate(m.node(e, a), d);
                }
                EXPECT_NEAR(x, g.x[static_cast<std::size_t>(d)], 1e-14) << set;
            }
            const double on_face =
                std::max({std::abs(g.natural[0]), std::abs(g.natural[1]), std::abs(g.natural[2])});
            EXPECT_NEAR(on_face, 1.0, 1e-15);
        }
    }
    // Displaced master: the top of a box translated by u; gaps and Eq. A13 increments.
    const Mesh b = box_mesh({2.0, 2.0, 1.0, 2, 2, 1, {0.0, 0.0, -1.0}});
    MortarSurface3D s(b, "top");
    std::vector<double> u(b.coordinates.size());
    for (int a = 0; a < b.n_nodes(); ++a) {
        u[static_cast<std::size_t>(3 * a)] = 0.05;
        u[static_cast<std::size_t>(3 * a + 1)] = -0.02;
        u[static_cast<std::size_t>(3 * a + 2)] = 0.1;
    }
    s.set_configuration(b, &u);
    const auto p = s.project({0.55, 1.2, 0.3});
    ASSERT_TRUE(p.in_contact);
    EXPECT_NEAR(p.x[0], 0.55, 1e-13);
    EXPECT_NEAR(p.x[1], 1.2, 1e-13);
    EXPECT_NEAR(normal_gap(p, {0.55, 1.2, 0.3}), 0.2, 1e-13);
    const auto dgT = tangential_gap_increments(p, u, {0.02, 0.01, 0.3});
    EXPECT_NEAR(dgT[0], 0.05 - 0.02, 1e-14);  // master minus slave along t1 = +x
    EXPECT_NEAR(dgT[1], -0.02 - 0.01, 1e-14); // along t2 = +y
}

// --- Mortar contact pair --------------------------------------------------------------------

// Appends mesh b to m; b's face sets are renamed prefix + name.
void append(Mesh& m, const Mesh& b, const std::string& prefix) {
    const int base = m.n_nodes();
    const int ebase = m.n_elements();
    m.type = ElementType::hex8;
    m.coordinates.insert(m.coordinates.end(), b.coordinates.begin(), b.coordinates.end());
    for (int c : b.connectivity) {
        m.connectivity.push_back(c + base);
    }
    for (const auto& [name, faces] : b.face_sets) {
        auto& to = m.face_sets[prefix + name];
        for (const FaceRef& f : faces) {
            to.push_back({f.element + ebase, f.local_face});
        }
    }
    for (const auto& [name, nodes] : b.node_sets) {
        auto& to = m.node_sets[prefix + name];
        for (int a : nodes) {
            to.push_back(a + base);
        }
    }
}

// Master box under z = 0 (face set "m_top"), slave box above z = -pen ("s_bottom").
Mesh two_boxes(const BoxSpec& master, const BoxSpec& slave) {
    Mesh m;
    append(m, box_mesh(master), "m_");
    append(m, box_mesh(slave), "s_");
    m.validate();
    return m;
}

// Penalty normal law t_N = k_N g_N and Coulomb friction on tau = k_T dg_T (conjugate to
// Eq. A13), with the exact Jacobian; linear (no contact switch) when `coulomb` is false.
struct Law {
    double k_N = 1e5;
    double k_T = 5e4;
    double mu = 0.4;
    bool coulomb = false;
    std::vector<ContactTraction> operator()(const MortarContact<3>& c) const {
        std::vector<ContactTraction> out(c.n_points());
        for (std::size_t i = 0; i < out.size(); ++i) {
            const ContactKinematics& p = c.point(i);
            if (!p.active) {
                continue;
            }
            ContactTraction& t = out[i];
            // d g_N / d u: slave +n, master -n; d dg_T[k] / d u: slave -t_k, master +t_k.
            std::array<double, 6> dgN{};
            std::array<std::array<double, 6>, 2> dgT{};
            for (std::size_t d = 0; d < 3; ++d) {
                dgN[d] = p.n[d];
                dgN[3 + d] = -p.n[d];
                dgT[0][d] = -p.t1[d];
                dgT[0][3 + d] = p.t1[d];
                dgT[1][d] = -p.t2[d];
                dgT[1][3 + d] = p.t2[d];
            }
            t.t_N = k_N * p.g_N;
            const std::array<double, 2> trial{k_T * p.dg_T[0], k_T * p.dg_T[1]};
            const double mag = std::hypot(trial[0], trial[1]);
            const double limit = -mu * t.t_N;
            const bool slip = coulomb && mag > limit;
            for (std::size_t c6 = 0; c6 < 6; ++c6) {
                t.jac[0][c6] = k_N * dgN[c6];
            }
            if (!slip) {
                t.tau = trial;
                for (std::size_t k = 0; k < 2; ++k) {
                    for (std::size_t c6 = 0; c6 < 6; ++c6) {
                        t.jac[1 + k][c6] = k_T * dgT[k][c6];
                    }
                }
                continue;
            }
            const std::array<double, 2> e{trial[0] / mag, trial[1] / mag};
            t.tau = {limit * e[0], limit * e[1]};
            for (std::size_t k = 0; k < 2; ++k) {
                for (std::size_t c6 = 0; c6 < 6; ++c6) {
                    double de = 0.0; // d e_k = (I - e e) d trial / |trial|
                    for (std::size_t l = 0; l < 2; ++l) {
                        de += ((k == l ? 1.0 : 0.0) - e[k] * e[l]) * k_T * dgT[l][c6] / mag;
                    }
                    t.jac[1 + k][c6] = -mu * t.jac[0][c6] * e[k] + limit * de;
                }
            }
        }
        return out;
    }
};

std::vector<double> forces(MortarContact<3>& c, const Law& law, const std::vector<double>& du,
                           std::vector<ContactTriplet>* K) {
    c.update_gaps(du);
    const auto tr = law(c);
    std::vector<double> f(du.size(), 0.0);
    c.assemble(tr, f, K);
    return f;
}

Vec3 resultant(const std::vector<double>& f, const std::vector<int>& nodes) {
    Vec3 s{};
    for (int a : nodes) {
        for (std::size_t d = 0; d < 3; ++d) {
            s[d] += f[static_cast<std::size_t>(3 * a) + d];
        }
    }
    return s;
}

// Consistent nodal loads of a unit uniform traction on the rectangular faces of `set`.
std::map<int, double> consistent_areas(const Mesh& m, const std::string& set) {
    std::map<int, double> A;
    for (const FaceRef& f : m.face_set(set)) {
        const auto local = face_nodes(m.type, f.local_face);
        const int a = m.node(f.element, local[0]);
        const int b = m.node(f.element, local[1]);
        const int c = m.node(f.element, local[3]);
        const double l1 = std::hypot(m.coordinate(b, 0) - m.coordinate(a, 0),
                                     m.coordinate(b, 1) - m.coordinate(a, 1));
        const double l2 = std::hypot(m.coordinate(c, 0) - m.coordinate(a, 0),
                                     m.coordinate(c, 1) - m.coordinate(a, 1));
        for (int l : local) {
            A[m.node(f.element, l)] += 0.25 * l1 * l2;
        }
    }
    return A;
}

TEST(MortarContact3D, UniformTractionsOnNonMatchingMeshes) {
    const double pen = 1e-3;
    const Mesh m = two_boxes({3.0, 2.0, 1.0, 3, 2, 1, {0.0, 0.0, -1.0}},
                             {2.4, 1.5, 1.0, 4, 3, 1, {0.2, 0.3, -pen}});
    MortarContact<3> c(m, "s_bottom", "m_top");
    const std::vector<double> u(m.coordinates.size(), 0.0);
    EXPECT_TRUE(c.pair(m, u));
    EXPECT_FALSE(c.pair(m, u)); // same configuration, same pairing
    ASSERT_EQ(c.n_points(), 4U * 12U);
    const auto slave = m.nodes_of_faces("s_bottom");
    const auto master = m.nodes_of_faces("m_top");
    const auto areas = consistent_areas(m, "s_bottom");
    // The interface view: active, frame of the flat master, slave natural coordinates that
    // reproduce the point in its element.
    for (std::size_t i = 0; i < c.n_points(); ++i) {
        const ContactKinematics& k = c.point(i);
        ASSERT_TRUE(k.active);
        EXPECT_NEAR(k.g_N, -pen, 1e-15);
        EXPECT_NEAR(k.n[2], 1.0, 1e-15);
        EXPECT_NEAR(k.weight, 0.6 * 0.5 / 4.0, 1e-15); // weight 1 x area / 4
        double N[8];
        Shape<ElementType::hex8>::values(k.slave_natural.data(), N);
        for (int d = 0; d < 3; ++d) {
            double x = 0.0;
            for (int a = 0; a < 8; ++a) {
                x += N[a] * m.coordinate(m.node(k.slave_element, a), d);
            }
            EXPECT_NEAR(x, k.x[static_cast<std::size_t>(d)], 1e-14);
        }
    }
    // Uniform pressure p = k_N pen: the slave nodes carry the consistent loads, the master
    // the opposite total, no tangential and no net moment.
    Law law;
    const auto f = forces(c, law, u, nullptr);
    const double p = law.k_N * pen;
    const double A = 2.4 * 1.5;
    const Vec3 Fs = resultant(f, slave);
    const Vec3 Fm = resultant(f, master);
    EXPECT_NEAR(Fs[2], -p * A, 1e-12 * p * A);
    EXPECT_NEAR(Fm[2], p * A, 1e-12 * p * A);
    for (std::size_t d = 0; d < 2; ++d) {
        EXPECT_NEAR(Fs[d], 0.0, 1e-12 * p * A);
        EXPECT_NEAR(Fm[d], 0.0, 1e-12 * p * A);
    }
    for (const auto& [node, a] : areas) {
        EXPECT_NEAR(f[static_cast<std::size_t>(3 * node + 2)], -p * a, 1e-12 * p);
    }
    double mx = 0.0;
    double my = 0.0;
    for (int a = 0; a < m.n_nodes(); ++a) {
        mx += m.coordinate(a, 1) * f[static_cast<std::size_t>(3 * a + 2)];
        my += m.coordinate(a, 0) * f[static_cast<std::size_t>(3 * a + 2)];
    }
    EXPECT_NEAR(mx, 0.0, 1e-11 * p * A);
    EXPECT_NEAR(my, 0.0, 1e-11 * p * A);
    // A uniform tangential traction (tau1, tau2) along (t1, t2) = (x, y): consistent loads.
    std::vector<ContactTraction> tr(c.n_points());
    for (auto& t : tr) {
        t.tau = {30.0, -12.0};
    }
    std::vector<double> g(u.size(), 0.0);
    c.assemble(tr, g, nullptr);
    for (const auto& [node, a] : areas) {
        EXPECT_NEAR(g[static_cast<std::size_t>(3 * node)], -30.0 * a, 1e-12 * 30.0);
        EXPECT_NEAR(g[static_cast<std::size_t>(3 * node + 1)], 12.0 * a, 1e-12 * 30.0);
        EXPECT_NEAR(g[static_cast<std::size_t>(3 * node + 2)], 0.0, 1e-12 * 30.0);
    }
    const Vec3 Gm = resultant(g, master);
    EXPECT_NEAR(Gm[0], 30.0 * A, 1e-12 * 30.0 * A);
    EXPECT_NEAR(Gm[1], -12.0 * A, 1e-12 * 30.0 * A);
}

void check_tangent(const Mesh& m, MortarContact<3>& c, const Law& law,
                   const std::vector<double>& du) {
    std::vector<ContactTriplet> K;
    forces(c, law, du, &K);
    std::map<std::pair<int, int>, double> Kd;
    for (const auto& t : K) {
        Kd[{t.row, t.col}] += t.value;
    }
    const auto couplings = c.couplings();
    for (const auto& [rc, v] : Kd) { // every entry lies in the coupling pattern
        EXPECT_TRUE(std::binary_search(couplings.begin(), couplings.end(),
                                       std::array<int, 2>{rc.first, rc.second}));
    }
    const double h = 1e-7;
    double max_err = 0.0;
    double max_k = 0.0;
    for (int j = 0; j < 3 * m.n_nodes(); ++j) {
        auto dp = du;
        dp[static_cast<std::size_t>(j)] += h;
        auto dm = du;
        dm[static_cast<std::size_t>(j)] -= h;
        const auto fp = forces(c, law, dp, nullptr);
        const auto fm = forces(c, law, dm, nullptr);
        for (int i = 0; i < 3 * m.n_nodes(); ++i) {
            const double fd =
                (fp[static_cast<std::size_t>(i)] - fm[static_cast<std::size_t>(i)]) / (2 * h);
            const auto it = Kd.find({i, j});
            const double k = it == Kd.end() ? 0.0 : it->second;
            max_err = std::max(max_err, std::abs(fd - k));
            max_k = std::max(max_k, std::abs(k));
        }
    }
    EXPECT_GT(max_k, 0.0);
    EXPECT_LT(max_err, 1e-6 * max_k) << "max |K - K_fd| " << max_err << " of " << max_k;
}

TEST(MortarContact3D, TangentMatchesFiniteDifferencesPenaltyAndSlip) {
    // Wavy master (smoothed normals vary from point to point), non-matching slave.
    Mesh m = two_boxes({3.0, 2.0, 1.0, 3, 2, 1, {0.0, 0.0, -1.0}},
                       {2.4, 1.5, 1.0, 4, 3, 1, {0.2, 0.3, -0.05}});
    for (int a : m.node_set("m_top")) {
        m.coordinates[static_cast<std::size_t>(3 * a + 2)] +=
            0.01 * std::sin(2.1 * m.coordinate(a, 0) + 1.3 * m.coordinate(a, 1));
    }
    MortarContact<3> c(m, "s_bottom", "m_top");
    const std::vector<double> u(m.coordinates.size(), 0.0);
    c.pair(m, u);
    const int n_master = 4 * 3 * 2;
    std::vector<double> du(m.coordinates.size(), 0.0);
    for (int a = 0; a < m.n_nodes(); ++a) {
        for (int d = 0; d < 3; ++d) {
            du[static_cast<std::size_t>(3 * a + d)] = 1e-5 * std::sin(1.3 * a + 0.7 * d);
        }
    }
    Law law;
    check_tangent(m, c, law, du); // linear penalty (tau = k_T dg_T)
    // Coulomb slip: a large relative tangential increment, |k_T dg_T| > mu |t_N| everywhere.
    law.coulomb = true;
    for (int a = n_master; a < m.n_nodes(); ++a) {
        du[static_cast<std::size_t>(3 * a)] += 0.1;
        du[static_cast<std::size_t>(3 * a + 1)] -= 0.06;
    }
    c.update_gaps(du);
    const auto tr = law(c);
    for (std::size_t i = 0; i < tr.size(); ++i) {
        ASSERT_TRUE(c.point(i).active);
        ASSERT_LT(tr[i].t_N, 0.0);
        EXPECT_NEAR(std::hypot(tr[i].tau[0], tr[i].tau[1]), -law.mu * tr[i].t_N,
                    1e-12 * std::abs(tr[i].t_N));
    }
    check_tangent(m, c, law, du);
}

// --- Elastic patch test ---------------------------------------------------------------------

struct PatchResult {
    double max_stress_error = 0.0; // max |sigma - sigma_exact| / p over all Gauss points
    double penetration = 0.0;      // mean -g_N
    std::vector<double> residuals;
};

// Two linear elastic hex8 blocks (master below z = 0, slave above) pressed together by a
// uniform pressure on the slave's top; rollers on x = 0 and y = 0 of both blocks and the
// master's bottom. Frictionless penalty contact; Newton with the contact tangent. The exact
// solution is a uniform uniaxial stress sigma_zz = -p and a uniform penetration p / k_N.
PatchResult press(int mx, int my, int sx, int sy) {
    const double E = 1e4, nu = 0.3, p = 100.0, k_N = 1e7;
    const Mesh m = two_boxes({2.0, 2.0, 1.0, mx, my, 1, {0.0, 0.0, -1.0}},
                             {2.0, 2.0, 1.0, sx, sy, 1, {0.0, 0.0, 0.0}});
    const int ndof = 3 * m.n_nodes();
    std::vector<bool> fixed(static_cast<std::size_t>(ndof), false);
    for (const char* b : {"m_", "s_"}) {
        for (int a : m.node_set(std::string(b) + "left")) {
            fixed[static_cast<std::size_t>(3 * a)] = true;
        }
        for (int a : m.node_set(std::string(b) + "front")) {
            fixed[static_cast<std::size_t>(3 * a + 1)] = true;
        }
    }
    for (int a : m.node_set("m_bottom")) {
        fixed[static_cast<std::size_t>(3 * a + 2)] = true;
    }
    Eigen::VectorXd f_ext = Eigen::VectorXd::Zero(ndof);
    for (const auto& [node, a] : consistent_areas(m, "s_top")) {
        f_ext[3 * node + 2] -= p * a;
    }
    const double lam = E * nu / ((1 + nu) * (1 - 2 * nu)), G = E / (2 * (1 + nu));
    double Dm[36] = {};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            Dm[6 * i + j] = lam + (i == j ? 2 * G : 0.0);
        }
        Dm[6 * (3 + i) + 3 + i] = 2 * G;
    }
    Eigen::MatrixXd K_el = Eigen::MatrixXd::Zero(ndof, ndof);
    const auto rule = gauss_rule<3>(false);
    auto element_X = [&](int e, double* X) {
        for (int a = 0; a < 8; ++a) {
            for (int d = 0; d < 3; ++d) {
                X[3 * a + d] = m.coordinate(m.node(e, a), d);
            }
        }
    };
    for (int e = 0; e < m.n_elements(); ++e) {
        double X[24], dNdx[24];
        element_X(e, X);
        Eigen::Matrix<double, 24, 24> Ke = Eigen::Matrix<double, 24, 24>::Zero();
        for (int q = 0; q < rule.n; ++q) {
            const double det =
                physical_gradients<3>(X, rule.xi[static_cast<std::size_t>(q)].data(), dNdx);
            add_tangent<3>(dNdx, Dm, det * rule.weight[static_cast<std::size_t>(q)], Ke);
        }
        for (int a = 0; a < 24; ++a) {
            for (int b = 0; b < 24; ++b) {
                K_el(3 * m.node(e, a / 3) + a % 3, 3 * m.node(e, b / 3) + b % 3) += Ke(a, b);
            }
        }
    }
    MortarContact<3> contact(m, "s_bottom", "m_top");
    std::vector<double> u(static_cast<std::size_t>(ndof), 0.0);
    contact.pair(m, u); // one increment: the pairing of the start configuration
    Law law;
    law.k_N = k_N;
    law.k_T = 0.0; // frictionless
    PatchResult res;
    for (int it = 0; it < 10; ++it) {
        std::vector<ContactTriplet> Kc;
        const auto f_c = forces(contact, law, u, &Kc); // the increment is the whole u here
        const Eigen::Map<const Eigen::VectorXd> uv(u.data(), ndof);
        Eigen::VectorXd R = f_ext - K_el * uv - Eigen::Map<const Eigen::VectorXd>(f_c.data(), ndof);
        Eigen::MatrixXd K = K_el;
        for (const auto& t : Kc) {
            K(t.row, t.col) += t.value;
        }
        for (int i = 0; i < ndof; ++i) {
            if (fixed[static_cast<std::size_t>(i)]) {
                R[i] = 0.0;
                K.row(i).setZero();
                K.col(i).setZero();
                K(i, i) = 1.0;
            }
        }
        res.residuals.push_back(R.norm() / f_ext.norm());
        if (R.norm() <= 1e-12 * f_ext.norm()) {
            break;
        }
        const Eigen::VectorXd du = K.partialPivLu().solve(R);
        for (int i = 0; i < ndof; ++i) {
            u[static_cast<std::size_t>(i)] += du[i];
        }
    }
    for (int e = 0; e < m.n_elements(); ++e) {
        double X[24], dNdx[24], ue[24];
        element_X(e, X);
        for (int a = 0; a < 24; ++a) {
            ue[a] = u[static_cast<std::size_t>(3 * m.node(e, a / 3) + a % 3)];
        }
        for (int q = 0; q < rule.n; ++q) {
            physical_gradients<3>(X, rule.xi[static_cast<std::size_t>(q)].data(), dNdx);
            const auto eps = strain_at<3>(dNdx, ue);
            const double tr = eps[0] + eps[1] + eps[2];
            for (std::size_t i = 0; i < 6; ++i) {
                const double s = 2 * G * eps[i] + (i < 3 ? lam * tr : 0.0);
                const double exact = i == 2 ? -p : 0.0;
                res.max_stress_error = std::max(res.max_stress_error, std::abs(s - exact) / p);
            }
        }
    }
    int n = 0;
    for (std::size_t i = 0; i < contact.n_points(); ++i) {
        if (contact.point(i).active) {
            res.penetration -= contact.point(i).g_N;
            ++n;
        }
    }
    res.penetration /= n;
    return res;
}

void print(const char* name, const PatchResult& r) {
    std::printf("%s: stress error %.2e, penetration %.6e, residuals", name, r.max_stress_error,
                r.penetration);
    for (double v : r.residuals) {
        std::printf(" %.1e", v);
    }
    std::printf("\n");
}

TEST(MortarContact3D, PatchTestNestedMeshesTransmitPressureExactly) {
    // Master nodes are slave nodes (slave finer): N_J is bilinear on every slave face, so the
    // slave faces' 2x2 Gauss rule integrates Eq. A20 exactly and the stress is uniform.
    const auto r = press(2, 2, 4, 4);
    print("nested", r);
    EXPECT_LT(r.max_stress_error, 1e-8);
    EXPECT_NEAR(r.penetration, 100.0 / 1e7, 1e-12);
    EXPECT_LE(r.residuals.size(), 3U); // linear: one Newton step
}

TEST(MortarContact3D, PatchTestGeneralNonMatchingMeshesSmallError) {
    // Master edges inside slave faces: N_J has kinks the 2x2 rule does not integrate
    // exactly; the resultant is still exact and the stress error small (bounded here).
    const auto r = press(3, 2, 4, 3);
    print("general", r);
    EXPECT_LT(r.max_stress_error, 2e-2);
    EXPECT_NEAR(r.penetration, 100.0 / 1e7, 1e-7);
    EXPECT_LE(r.residuals.size(), 3U);
}

// --- Sliding ----------------------------------------------------------------------------------

TEST(MortarContact3D, BlockSlidesOverSeveralMasterFaces) {
    // A slave block with one 0.8 x 0.8 face slides diagonally over a plate of 6 x 4 faces of
    // 0.5 in steps of (0.25, 0.1): the pairing changes, every point stays active while the
    // block is on the plate, the friction force is mu times the normal force opposing the
    // motion on both sides, and the block leaves the plate at the end.
    const double pen = 1e-3;
    const Mesh m = two_boxes({3.0, 2.0, 0.5, 6, 4, 1, {0.0, 0.0, -0.5}},
                             {0.8, 0.8, 0.5, 1, 1, 1, {0.05, 0.3, -pen}});
    MortarContact<3> c(m, "s_bottom", "m_top");
    std::vector<double> u(m.coordinates.size(), 0.0);
    Law law;
    law.coulomb = true;
    const auto slave = m.nodes_of_faces("s_bottom");
    const auto master = m.nodes_of_faces("m_top");
    const std::array<double, 2> step_u{0.25, 0.1};
    std::set<int> faces_seen;
    int full_steps = 0;
    const int steps = 12;
    for (int step = 0; step < steps; ++step) {
        c.pair(m, u);
        const double x0 = 0.05 + step * step_u[0];
        const double y0 = 0.3 + step * step_u[1];
        const bool on_plate = x0 + 0.8 <= 3.0 && y0 + 0.8 <= 2.0;
        int active = 0;
        for (std::size_t i = 0; i < c.n_points(); ++i) {
            active += c.point(i).active ? 1 : 0;
            if (c.point(i).active) {
                faces_seen.insert(c.master_segment(i));
            }
        }
        std::vector<double> du(u.size(), 0.0); // the whole block slides
        for (int a : m.node_set("s_all")) {
            du[static_cast<std::size_t>(3 * a)] = step_u[0];
            du[static_cast<std::size_t>(3 * a + 1)] = step_u[1];
        }
        const auto f = forces(c, law, du, nullptr);
        for (std::size_t i = 0; i < u.size(); ++i) {
            u[i] += du[i];
        }
        if (!on_plate) {
            continue;
        }
        EXPECT_EQ(active, 4) << "step " << step; // no inactive point while inside
        ++full_steps;
        const Vec3 Fs = resultant(f, slave);
        const Vec3 Fm = resultant(f, master);
        EXPECT_NEAR(Fs[2], -law.k_N * pen * 0.64, 1e-9);
        const double T = std::hypot(Fs[0], Fs[1]);
        EXPECT_NEAR(T, law.mu * std::abs(Fs[2]), 1e-9);
        // Friction on the slave resists its motion: internal force along +motion.
        EXPECT_NEAR(Fs[0] * step_u[1] - Fs[1] * step_u[0], 0.0, 1e-9);
        EXPECT_GT(Fs[0], 0.0);
        for (std::size_t d = 0; d < 3; ++d) {
            EXPECT_NEAR(Fm[d], -Fs[d], 1e-9);
        }
    }
    // Keep sliding until beyond the plate's free border: no point in contact.
    for (int a : m.node_set("s_all")) {
        u[static_cast<std::size_t>(3 * a)] += 3.0;
    }
    c.pair(m, u);
    for (std::size_t i = 0; i < c.n_points(); ++i) {
        EXPECT_FALSE(c.point(i).active);
    }
    const auto& counters = c.projection_counters();
    EXPECT_EQ(counters.pairings, steps + 1);
    EXPECT_EQ(counters.projections, 4 * (steps + 1));
    EXPECT_GE(counters.pattern_changes, 6);
    EXPECT_GE(full_steps, 7);
    EXPECT_GE(faces_seen.size(), 8U);
    EXPECT_LE(counters.projection_iterations, 20 * counters.projections);
}

} // namespace
