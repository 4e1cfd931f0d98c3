#pragma once
// Mortar contact forces (paper Eqs. A20, A21) and their tangent for 2D (quad4 plane strain),
// integrated at the 2-point Gauss points of the slave edges.
//
// Pairing per increment: at the start of an increment every slave integration point is
// projected onto the master (ContactSurface2D::project, Eq. A9) in the converged
// configuration; the projection (master edge, xi, frame n, t) is then held fixed during the
// Newton iterations of the increment, so within an increment
//   g_N  = g_N0 + (du_s - sum_J N_J du_J) . n        (Eq. A11, linearised in the increment)
//   dg_T = (sum_J N_J du_J - du_s) . t               (Eq. A13)
// are linear in the increment and the tangent below is the exact derivative of the residual
// (the frame and xi move only between increments: small slip per increment). A point whose
// projection crosses a natural border is inactive for the increment.
//
// Forces: the contact's virtual work t_N dg_N + tau dg_T gives the internal forces
//   slave node a:   N_a (t_N n - tau t) w j,    master node J: N_J (tau t - t_N n) w j,
// with tau conjugate to Eq. A13's dg_T (tau = k_T dg_T while sticking), t_N < 0 in
// compression. The traction and its Jacobian d(t_N, tau)/d(u_s, u_m) of the point (the layout
// of the contact engine's outputs: slave columns, then master columns) come from the caller.

#include <array>
#include <span>
#include <string>
#include <vector>

#include "fem/contact_kinematics.hpp"
#include "fem/mesh.hpp"
#include "fem/mortar_surface.hpp"

namespace ifsim::fem {

struct ContactPointState {
    SlavePoint slave;
    SurfaceProjection master;
    double g_N0 = 0.0; // normal gap at the start of the increment
    double g_N = 0.0;  // current normal gap (Eq. A11)
    double dg_T = 0.0; // tangential gap increment (Eq. A13)
};

// The traction of one point and its Jacobian: jac[0] = d t_N / d(u_s x, u_s y, u_m x, u_m y),
// jac[1] = d tau / d(...), with u_m the displacement of the projected master point.
struct PointTraction {
    double t_N = 0.0;
    double tau = 0.0;
    std::array<std::array<double, 4>, 2> jac{};
};

class MortarContact2D : public MortarKinematics {
public:
    MortarContact2D(const Mesh& mesh, const std::string& slave_faces,
                    const std::string& master_faces);

    // The dimension-independent view (fem/contact_kinematics.hpp).
    int dim() const override { return 2; }
    std::size_t n_points() const override { return points_.size(); }
    const ContactKinematics& point(std::size_t i) const override { return view_[i]; }
    void assemble(std::span<const ContactTraction> traction, std::vector<double>& f_int,
                  std::vector<ContactTriplet>* K) const override;
    const ProjectionCounters& projection_counters() const override { return counters_; }

    // Projects every slave integration point in the configuration x + u (start of an
    // increment). Returns true when the pairing (active flags and master edges) changed, i.e.
    // the sparse pattern's contact couplings must be rebuilt.
    bool pair(const Mesh& mesh, const std::vector<double>& u) override;

    // Gaps of the active points for the displacement increment du (dim per node).
    void update_gaps(const std::vector<double>& du) override;

    const std::vector<ContactPointState>& points() const { return points_; }
    // The slave element face of a slave edge (for the stress extrapolation, Eq. 14).
    const FaceRef& slave_face(int edge) const { return slave_.edge_face(edge); }

    // Adds the contact forces to f_int (dim per node) and, when K is given, the tangent
    // entries d f_int / d u; `traction` has one entry per point (inactive points ignored).
    void assemble(std::span<const PointTraction> traction, std::vector<double>& f_int,
                  std::vector<ContactTriplet>* K) const;

    // DOF couplings of the current pairing (the pattern's contact entries).
    std::vector<std::array<int, 2>> couplings() const override;

private:
    ContactSurface2D slave_;
    ContactSurface2D master_;
    void refresh_view(std::size_t i);

    std::vector<ContactPointState> points_;
    std::vector<ContactKinematics> view_;
    ProjectionCounters counters_;
};

} // namespace ifsim::fem
