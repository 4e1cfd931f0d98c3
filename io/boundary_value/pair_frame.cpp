#include "io/boundary_value/pair_frame.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "fem/shape_functions.hpp"
#include "io/mesh/face_geometry.hpp"

namespace ifsim::io {

PairFrame pair_frame(const fem::Mesh& mesh, const std::string& slave_faces,
                     const std::array<double, 3>& shear_direction) {
    PairFrame f;
    f.n = face_set_geometry(mesh, slave_faces).normal;
    Vec3 t1 = shear_direction;
    if (mesh.dim() == 2) {
        t1[2] = 0.0;
    }
    const double dn = dot(t1, f.n);
    for (std::size_t d = 0; d < 3; ++d) {
        t1[d] -= dn * f.n[d];
    }
    const double len = std::sqrt(dot(t1, t1));
    if (!(len > 1.0e-12)) {
        throw std::invalid_argument(
            fmt::format("the shear direction ({}, {}, {}) is normal to the faces '{}'",
                        shear_direction[0], shear_direction[1], shear_direction[2], slave_faces));
    }
    for (double& c : t1) {
        c /= len;
    }
    f.t1 = t1;
    const Vec3& n = f.n;
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
