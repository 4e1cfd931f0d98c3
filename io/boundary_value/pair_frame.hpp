#pragma once
// Where history.csv measures a contact pair (docs/scenes.md "Outputs"): its own frame and the
// reference position of its points. n is the slave faces' area-weighted mean outward normal,
// t1 the pair's shear_direction projected onto the plane normal to n, t2 = t1 x n, so that
// (n2, t1, t2) is right-handed with the master's normal n2 = -n (paper Eq. 2). Reference
// configuration, fixed for the run.

#include <array>
#include <string>

#include "fem/contact_pair.hpp"
#include "fem/mesh.hpp"

namespace ifsim::io {

using Vec3 = std::array<double, 3>;

struct PairFrame {
    Vec3 n{}, t1{}, t2{};
};

inline double dot(const Vec3& a, const Vec3& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// A shear direction normal to the faces falls back to the first of the vertical axis and the
// other global axes with a part in their plane (as the contact engine keeps a frame there).
PairFrame pair_frame(const fem::Mesh& mesh, const std::string& slave_faces,
                     const std::array<double, 3>& shear_direction);

// The reference position of a contact point (its slave element's shape functions at the
// point's natural coordinates), and its displacement in u.
Vec3 contact_point_position(const fem::Mesh& mesh, const fem::ContactPointRecord& r,
                            const double* u = nullptr);

} // namespace ifsim::io
