#include "io/mesh/face_geometry.hpp"

#include <cmath>

namespace ifsim::io {

namespace {

using Vec3 = std::array<double, 3>;

Vec3 point(const fem::Mesh& mesh, int node) {
    Vec3 x{};
    for (int d = 0; d < mesh.dim(); ++d) {
        x[static_cast<std::size_t>(d)] = mesh.coordinate(node, d);
    }
    return x;
}

Vec3 minus(const Vec3& a, const Vec3& b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}

double length(const Vec3& a) {
    return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
}

} // namespace

FaceGeometry face_geometry(const fem::Mesh& mesh, const fem::FaceRef& face) {
    const auto local = fem::face_nodes(mesh.type, face.local_face);
    const auto node = [&](std::size_t k) { return point(mesh, mesh.node(face.element, local[k])); };
    FaceGeometry g;
    Vec3 n{};
    if (mesh.dim() == 2) {
        // Counter-clockwise elements: the edge a -> b has the outward normal (t_y, -t_x).
        const Vec3 t = minus(node(1), node(0));
        n = {t[1], -t[0], 0.0};
        g.area = length(t);
    } else {
        // Right-hand ordering: the diagonals' cross product points outwards, |d1 x d2| / 2 is
        // the area of a plane quadrilateral.
        const Vec3 d1 = minus(node(2), node(0));
        const Vec3 d2 = minus(node(3), node(1));
        n = {d1[1] * d2[2] - d1[2] * d2[1], d1[2] * d2[0] - d1[0] * d2[2],
             d1[0] * d2[1] - d1[1] * d2[0]};
        g.area = 0.5 * length(n);
    }
    const double len = length(n);
    for (std::size_t d = 0; d < 3; ++d) {
        g.normal[d] = len > 0.0 ? n[d] / len : 0.0;
    }
    return g;
}

FaceGeometry face_set_geometry(const fem::Mesh& mesh, const std::string& face_set) {
    FaceGeometry total;
    Vec3 n{};
    for (const fem::FaceRef& f : mesh.face_set(face_set)) {
        const FaceGeometry g = face_geometry(mesh, f);
        total.area += g.area;
        for (std::size_t d = 0; d < 3; ++d) {
            n[d] += g.area * g.normal[d];
        }
    }
    const double len = length(n);
    for (std::size_t d = 0; d < 3; ++d) {
        total.normal[d] = len > 0.0 ? n[d] / len : 0.0;
    }
    return total;
}

} // namespace ifsim::io
