#pragma once
// Mortar contact forces (paper Eqs. A20, A21) and their tangent for 3D (hex8), integrated at
// the 2x2 Gauss points of the slave faces; the 3D twin of MortarContact2D.
//
// Pairing per increment: at the start of an increment every slave integration point is
// projected onto the master (ContactSurface3D::project, Eqs. A15-A17) in the converged
// configuration; the projection (master face, xi, frame n, t1, t2) is then held fixed during
// the Newton iterations of the increment, so within an increment
//   g_N     = g_N0 + (du_s - sum_J N_J du_J) . n      (Eq. A11, linearised in the increment)
//   dg_T[k] = (sum_J N_J du_J - du_s) . t_k           (Eq. A13)
// are linear in the increment and the tangent below is the exact derivative of the residual.
// A point whose projection crosses a natural border is inactive for the increment.
//
// Forces: the contact's virtual work t_N dg_N + tau . dg_T gives the internal forces
//   slave node a:   N_a (t_N n - tau1 t1 - tau2 t2) w j,   master node J: the opposite with N_J.
// The traction's Jacobian columns are [0, 3) the slave point's displacement and [3, 6) the
// projected master point's (fem/contact_kinematics.hpp).

#include <array>
#include <span>
#include <string>
#include <vector>

#include "fem/contact_kinematics.hpp"
#include "fem/mesh.hpp"
#include "fem/mortar_surface_3d.hpp"

namespace ifsim::fem {

struct ContactPointState3D {
    SlavePoint3D slave;
    SurfaceProjection3D master;
    double g_N0 = 0.0;            // normal gap at the start of the increment
    double g_N = 0.0;             // current normal gap (Eq. A11)
    std::array<double, 2> dg_T{}; // tangential gap increments along t1, t2 (Eq. A13)
};

class MortarContact3D : public MortarKinematics {
public:
    MortarContact3D(const Mesh& mesh, const std::string& slave_faces,
                    const std::string& master_faces);

    int dim() const override { return 3; }
    std::size_t n_points() const override { return points_.size(); }
    const ContactKinematics& point(std::size_t i) const override { return view_[i]; }
    const ProjectionCounters& projection_counters() const override { return counters_; }

    // Projects every slave integration point in the configuration x + u (start of an
    // increment). Returns true when the pairing (active flags and master faces) changed.
    bool pair(const Mesh& mesh, const std::vector<double>& u) override;
    // Gaps of the active points for the displacement increment du (3 per node).
    void update_gaps(const std::vector<double>& du) override;
    void assemble(std::span<const ContactTraction> traction, std::vector<double>& f_int,
                  std::vector<ContactTriplet>* K) const override;
    std::vector<std::array<int, 2>> couplings() const override;

    const std::vector<ContactPointState3D>& points() const { return points_; }
    const ContactSurface3D& slave_surface() const { return slave_; }
    const ContactSurface3D& master_surface() const { return master_; }

private:
    void refresh_view(std::size_t i);

    ContactSurface3D slave_;
    ContactSurface3D master_;
    std::vector<ContactPointState3D> points_;
    std::vector<ContactKinematics> view_;
    ProjectionCounters counters_;
};

} // namespace ifsim::fem
