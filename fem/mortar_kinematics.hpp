#pragma once
// The dimension-independent view of a mortar contact pair that the static solver and the
// contact pairs (Coulomb, continuum interface) work with: per slave integration point the
// gaps, the local frame and where the point sits in its slave element (for the stress
// extrapolation of Eq. 14); forces and tangent from the tractions (Eqs. A20, A21).
//
// Conventions (both dimensions): the gap is g = x(1) - x(2), slave minus master (Eq. 7);
// g_N = g . n < 0 is penetration; n is the master's outward normal (towards the slave); the
// tangential gap increments dg_T[k] = (du_master - du_slave) . t_k (Eq. A13); the traction's
// tau[k] is conjugate to dg_T[k] and t_N < 0 in compression, so the slave node a gets
// f_a = N_a (t_N n - tau_1 t1 - tau_2 t2) w j and the master nodes the opposite. In 2D
// t2 = e3 and dg_T[1] = tau[1] = 0.

#include <array>
#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "fem/mesh.hpp"

namespace ifsim::fem {

struct ContactKinematics {
    bool active = false; // the point projects inside the master surface
    double g_N = 0.0;    // current normal gap (linearised in the increment)
    std::array<double, 2> dg_T{};
    std::array<double, 3> n{}, t1{}, t2{}; // local frame, global components
    int slave_element = -1;                // element of the slave face
    std::array<double, 3> slave_natural{}; // natural coordinates in that element
    double weight = 0.0;                   // Gauss weight times surface Jacobian
    std::array<double, 3> x{};             // slave point, current configuration
};

// Traction of a point and its Jacobian: jac[comp][c] = d (t_N, tau1, tau2)[comp] / d u_c with
// c in [0, dim) the slave point's displacement and [dim, 2 dim) the projected master point's
// (the layout of the contact engines' outputs).
struct ContactTraction {
    double t_N = 0.0;
    std::array<double, 2> tau{};
    std::array<std::array<double, 6>, 3> jac{};
};

struct ContactTriplet {
    int row = 0; // global DOF (dim * node + direction)
    int col = 0;
    double value = 0.0;
};

struct ProjectionCounters {
    long pairings = 0;    // calls of pair()
    long projections = 0; // slave points projected
    long projection_iterations = 0;
    long pattern_changes = 0; // pairings that changed the DOF couplings
};

class MortarKinematics {
public:
    virtual ~MortarKinematics() = default;
    virtual int dim() const = 0;
    virtual std::size_t n_points() const = 0;

    // Projects every slave integration point in the configuration x + u (start of an
    // increment) and holds the projection fixed for the increment. Returns true when the DOF
    // couplings changed (the sparse pattern must be rebuilt).
    virtual bool pair(const Mesh& mesh, const std::vector<double>& u) = 0;
    // Gaps of the active points for the displacement increment du (dim per node).
    virtual void update_gaps(const std::vector<double>& du) = 0;
    virtual const ContactKinematics& point(std::size_t i) const = 0;

    // Adds the contact internal forces to f_int (dim per node) and, when K is given, appends
    // the tangent entries d f_int / d u; one traction per point, inactive points ignored.
    virtual void assemble(std::span<const ContactTraction> traction, std::vector<double>& f_int,
                          std::vector<ContactTriplet>* K) const = 0;
    // Global DOF pairs coupled by the current pairing (sorted, unique).
    virtual std::vector<std::array<int, 2>> couplings() const = 0;
    virtual const ProjectionCounters& projection_counters() const = 0;
};

// MortarContact<2> or <3> (fem/mortar_contact.hpp) by the mesh's dimension. The pairs see the
// interface only: which concrete class it is stays in mortar_contact.cpp.
std::unique_ptr<MortarKinematics> make_mortar_contact(const Mesh& mesh,
                                                      const std::string& slave_faces,
                                                      const std::string& master_faces);

} // namespace ifsim::fem
