#include "io/boundary_value/pair_frame.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "fem/shape_functions.hpp"
#include "io/mesh/face_geometry.hpp"

namespace ifsim::io {

namespace {

// d projected onto the plane normal to n and normalised; false when d is (nearly) normal to it.
bool in_plane(Vec3 d, const Vec3& n, Vec3& out) {
    const double dn = dot(d, n);
    for (std::size_t k = 0; k < 3; ++k) {
        d[k] -= dn * n[k];
    }
    const double len = std::sqrt(dot(d, d));
    if (!(len > 1.0e-12)) {
        return false;
    }
    for (std::size_t k = 0; k < 3; ++k) {
        out[k] = d[k] / len;
    }
    return true;
}

} // namespace

PairFrame pair_frame(const fem::Mesh& mesh, const std::string& slave_faces,
                     const std::array<double, 3>& shear_direction) {
    PairFrame f;
    f.n = face_set_geometry(mesh, slave_faces).normal;
    Vec3 d = shear_direction;
    if (mesh.dim() == 2) {
        d[2] = 0.0;
    }
    // A shear direction normal to the faces (the default +x on a wall normal to x) falls back
    // to the first of the vertical axis and the others with a part in the plane.
    const std::array<Vec3, 3> fallback =
        mesh.dim() == 2 ? std::array<Vec3, 3>{Vec3{0, 1, 0}, Vec3{1, 0, 0}, Vec3{0, 0, 0}}
                        : std::array<Vec3, 3>{Vec3{0, 0, 1}, Vec3{0, 1, 0}, Vec3{1, 0, 0}};
    bool found = in_plane(d, f.n, f.t1);
    for (std::size_t k = 0; k < fallback.size() && !found; ++k) {
        found = in_plane(fallback[k], f.n, f.t1);
    }
    if (!found) {
        throw std::invalid_argument(
            fmt::format("the faces '{}' have no mean normal (an empty set?)", slave_faces));
    }
    const Vec3& n = f.n;
    const Vec3& t1 = f.t1;
    f.t2 = {t1[1] * n[2] - t1[2] * n[1], t1[2] * n[0] - t1[0] * n[2], t1[0] * n[1] - t1[1] * n[0]};
    return f;
}

Vec3 contact_point_position(const fem::Mesh& mesh, const fem::ContactPointRecord& r,
                            const double* u) {
    Vec3 x{};
    if (r.slave_element < 0) {
        return x;
    }
    const int D = mesh.dim();
    std::array<double, 8> N{};
    if (mesh.type == fem::ElementType::quad4) {
        fem::Shape<fem::ElementType::quad4>::values(r.natural.data(), N.data());
    } else {
        fem::Shape<fem::ElementType::hex8>::values(r.natural.data(), N.data());
    }
    for (int a = 0; a < mesh.nodes_per_element(); ++a) {
        const auto node = static_cast<std::size_t>(mesh.node(r.slave_element, a));
        for (int d = 0; d < D; ++d) {
            const double v =
                u != nullptr ? u[node * static_cast<std::size_t>(D) + static_cast<std::size_t>(d)]
                             : mesh.coordinates[node * static_cast<std::size_t>(D) +
                                                static_cast<std::size_t>(d)];
            x[static_cast<std::size_t>(d)] += N[static_cast<std::size_t>(a)] * v;
        }
    }
    return x;
}

} // namespace ifsim::io
