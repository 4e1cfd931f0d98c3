#pragma once
// A 2D contact surface (quad4 plane strain): the edges of a face set as a chain of linear
// segments, with the projection of a point onto it (paper Eqs. A9/A10) and the gaps of
// Eqs. A11/A13. Orientation: an edge runs from its first to its second node as listed by
// face_nodes() (counter-clockwise elements), so its outward normal is the tangent turned
// clockwise, n = (t_y, -t_x). The master normal thus points out of the master body, towards
// the slave; the gap convention is g = x(1) - x(2) (slave minus master, Eq. 7), g_N = g . n.
//
// Kinks: the tangent used by the projection is smoothed — the averaged unit tangents of the
// edges meeting at a node, interpolated linearly along each edge (the paper interpolates
// x_xi quadratically; linear interpolation of nodal tangents gives the same continuity of
// the projection residual across nodes with fewer operations).

#include <array>
#include <string>
#include <vector>

#include "fem/mesh.hpp"

namespace ifsim::fem {

struct SurfaceProjection {
    bool in_contact = false;         // false: the point projects beyond a natural border
    int edge = -1;                   // edge of the chain
    double xi = 0.0;                 // convective coordinate on the edge, [-1, 1]
    std::array<double, 2> N{};       // master shape functions at xi (Eq. A1)
    std::array<int, 2> nodes{};      // master nodes of the edge
    std::array<double, 2> x{};       // projected point
    std::array<double, 2> normal{};  // smoothed unit normal (towards the slave)
    std::array<double, 2> tangent{}; // smoothed unit tangent, tangent x normal = -e3
    int iterations = 0;              // Newton iterations over all visited edges
};

// An integration point of a slave edge (2-point Gauss).
struct SlavePoint {
    int edge = 0;
    double xi = 0.0;            // on the slave edge
    std::array<double, 2> N{};  // slave shape functions
    std::array<int, 2> nodes{}; // slave nodes
    double weight_j = 0.0;      // Gauss weight times edge Jacobian (half length)
    std::array<double, 2> x{};
};

class MortarSurface2D {
public:
    // Edges of the face set; throws std::invalid_argument for a 3D mesh or an empty set.
    MortarSurface2D(const Mesh& mesh, const std::string& face_set);

    int n_edges() const { return static_cast<int>(edges_.size()); }
    const std::array<int, 2>& edge_nodes(int e) const {
        return edges_[static_cast<std::size_t>(e)];
    }
    const FaceRef& edge_face(int e) const { return faces_[static_cast<std::size_t>(e)]; }
    int next(int e) const { return next_[static_cast<std::size_t>(e)]; }
    int previous(int e) const { return prev_[static_cast<std::size_t>(e)]; }

    // Coordinates: the reference mesh plus an optional displacement field (dim per node).
    void set_configuration(const Mesh& mesh, const std::vector<double>* displacement);

    // Orthogonal projection of p (Eq. A9) by Newton (Eq. A10 with the smoothed tangent),
    // starting on edge `start` (-1: the nearest edge), continuing on the neighbouring edge
    // when xi leaves [-1, 1]. Beyond the chain's ends the point is not in contact.
    SurfaceProjection project(const std::array<double, 2>& p, int start = -1) const;

    // The 2-point Gauss points of every edge in the current configuration.
    std::vector<SlavePoint> integration_points() const;

private:
    std::array<double, 2> node_x(int node) const;
    std::array<double, 2> nodal_tangent(int e, int end) const;

    std::vector<std::array<int, 2>> edges_;
    std::vector<FaceRef> faces_;
    std::vector<int> next_, prev_;
    std::vector<double> x_; // current coordinates of all mesh nodes
};

// Normal gap (Eq. A11, sign of Eq. 7: slave minus master, negative = penetration).
double normal_gap(const SurfaceProjection& m, const std::array<double, 2>& slave_x);

// Tangential gap increment (Eq. A13): master minus slave increment along the tangent.
double tangential_gap_increment(const SurfaceProjection& m, const std::vector<double>& du,
                                const std::array<double, 2>& slave_du);

} // namespace ifsim::fem
