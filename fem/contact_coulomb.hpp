#pragma once
// The call the static solver makes for a 2D Coulomb contact pair: mortar kinematics
// (MortarContact2D), penalty normal traction t_N = k_N g_N while g_N <= 0, Coulomb friction and
// its exact Jacobian from the engine (engine/coulomb_contact.hpp), forces and tangent triplets
// on global DOFs (2 * node + direction).
//
// Per increment: begin_increment(u) (pairing; true -> rebuild the pattern with couplings());
// per Newton iteration: forces(du, f_int, &K) (residual and tangent of the same state); after
// convergence: commit().

#include <string>
#include <vector>

#include "engine/coulomb_contact.hpp"
#include "fem/contact_assembly.hpp"

namespace ifsim::fem {

struct CoulombContactSpec {
    std::string slave_faces;
    std::string master_faces;
    double normal_penalty = 1e6; // k_N, kPa/m
    CoulombParams friction;
};

class CoulombContact2D {
public:
    CoulombContact2D(const Mesh& mesh, CoulombContactSpec spec);

    bool begin_increment(const Mesh& mesh, const std::vector<double>& u);
    // Adds the contact internal forces for the increment du to f_int and, when K is given,
    // appends the tangent entries. Returns the number of closed points.
    int forces(const std::vector<double>& du, std::vector<double>& f_int,
               std::vector<ContactTriplet>* K);
    void commit() { points_.commit(); }

    std::vector<std::array<int, 2>> couplings() const { return mortar_.couplings(); }
    const MortarContact2D& mortar() const { return mortar_; }
    const std::vector<PointTraction>& tractions() const { return traction_; }

private:
    CoulombContactSpec spec_;
    MortarContact2D mortar_;
    CoulombContactPoints points_;
    std::vector<PointTraction> traction_;
};

} // namespace ifsim::fem
