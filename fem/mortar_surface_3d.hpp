#pragma once
// A 3D contact surface (hex8): the faces of a face set as bilinear 4-node quads, with the
// projection of a point onto it (paper Eqs. A15-A17) and the gaps of Eqs. A11/A13.
// Orientation: a face's nodes are listed by face_nodes() with the outward normal by the right
// hand rule, so x_xi1 x x_xi2 points out of the body; the master normal points towards the
// slave and the gap is g = x(1) - x(2) (slave minus master, Eq. 7), g_N = g . n.
//
// Kinks: the normal used by the projection is smoothed (the paper smooths x_xi for linear
// elements) — the unit face normals meeting at a node are averaged into a nodal normal, which
// is interpolated bilinearly over each face and normalised. Both the position and the smoothed
// normal are then continuous across shared edges, so the projection condition "x(xi) - p is
// along the smoothed normal" has a continuous residual along the whole surface.

#include <array>
#include <string>
#include <vector>

#include "fem/mesh.hpp"

namespace ifsim::fem {

using Vec3 = std::array<double, 3>;

struct SurfaceProjection3D {
    bool in_contact = false;    // false: the point projects beyond a natural border
    int face = -1;              // face of the surface
    std::array<double, 2> xi{}; // convective coordinates on the face, [-1, 1]^2
    std::array<double, 4> N{};  // master shape functions at xi (Eq. A1)
    std::array<int, 4> nodes{}; // master nodes of the face (face_nodes() order)
    Vec3 x{};                   // projected point
    Vec3 normal{};              // smoothed unit normal (towards the slave)
    Vec3 t1{}, t2{};            // t1 along x_xi1 orthogonal to n, t2 = n x t1
    int iterations = 0;         // Newton iterations over all visited faces
};

// An integration point of a slave face (2x2 Gauss).
struct SlavePoint3D {
    int face = 0;
    std::array<double, 2> xi{}; // on the slave face
    std::array<double, 4> N{};  // slave shape functions
    std::array<int, 4> nodes{}; // slave nodes
    double weight_j = 0.0;      // Gauss weight times area Jacobian |x_xi1 x x_xi2|
    Vec3 x{};
    Vec3 natural{}; // natural coordinates in the face's hex8 element
};

class MortarSurface3D {
public:
    // Faces of the face set; throws std::invalid_argument for a 2D mesh or an empty set.
    MortarSurface3D(const Mesh& mesh, const std::string& face_set);

    int n_faces() const { return static_cast<int>(faces_.size()); }
    const std::array<int, 4>& face_nodes_of(int f) const {
        return faces_[static_cast<std::size_t>(f)];
    }
    const FaceRef& face_ref(int f) const { return refs_[static_cast<std::size_t>(f)]; }
    // Face across edge k (local nodes k, k+1 mod 4) of face f; -1 on the free border.
    int neighbour(int f, int k) const {
        return neighbours_[static_cast<std::size_t>(f)][static_cast<std::size_t>(k)];
    }

    // Coordinates: the reference mesh plus an optional displacement field (3 per node); also
    // recomputes the smoothed nodal normals.
    void set_configuration(const Mesh& mesh, const std::vector<double>* displacement);

    // Orthogonal projection of p along the smoothed normal (Eqs. A15, A16) by Newton on
    // (xi1, xi2) (Eq. A17), starting on face `start` (-1: the nearest face), continuing onto
    // the neighbouring face when xi leaves [-1, 1]^2. Beyond the surface's free border the
    // point is not in contact.
    SurfaceProjection3D project(const Vec3& p, int start = -1) const;

    // Smoothed unit normal at xi on face f.
    Vec3 smoothed_normal(int f, const std::array<double, 2>& xi) const;

    // The 2x2 Gauss points of every face in the current configuration.
    std::vector<SlavePoint3D> integration_points() const;

private:
    struct Local; // geometry of one face at one xi
    Local evaluate(int f, const std::array<double, 2>& xi) const;
    static std::array<double, 2> newton_step(const Local& L, const Vec3& p, bool& converged);
    Vec3 node_x(int node) const;
    int nearest_face(const Vec3& p, std::array<double, 2>& xi) const;
    std::array<double, 2> across(int f, int k, const std::array<double, 2>& xi, int g) const;

    std::vector<std::array<int, 4>> faces_;
    std::vector<FaceRef> refs_;
    std::vector<std::array<int, 4>> neighbours_;
    std::vector<int> surface_index_;          // mesh node -> surface node (-1: not on it)
    std::vector<std::array<int, 4>> face_sn_; // surface node of each face corner
    std::vector<Vec3> nodal_normal_;          // per surface node
    std::vector<double> x_;                   // current coordinates of all mesh nodes
};

// Natural coordinates in a hex8 element of the point (s1, s2) of its local face f (bilinear
// between the face's corner nodes, as the element map is on the face).
Vec3 hex8_face_point(int local_face, const std::array<double, 2>& s);

// Normal gap (Eq. A11, sign of Eq. 7: slave minus master, negative = penetration).
double normal_gap(const SurfaceProjection3D& m, const Vec3& slave_x);

// Tangential gap increments (Eq. A13) along t1 and t2: master minus slave increment.
std::array<double, 2> tangential_gap_increments(const SurfaceProjection3D& m,
                                                const std::vector<double>& du,
                                                const Vec3& slave_du);

} // namespace ifsim::fem
