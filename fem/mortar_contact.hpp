#pragma once
// Mortar contact of two face sets, one code for 2D (quad4 plane strain, 2-point Gauss on the
// slave edges) and 3D (hex8, 2x2 Gauss on the slave faces): pairing, gaps, forces (paper Eqs.
// A20, A21) and their tangent. The surfaces (projection, Eqs. A9/A10 in 2D, A15-A17 in 3D)
// are fem/mortar_surface_2d.hpp and fem/mortar_surface_3d.hpp.
//
// Pairing per increment: at the start of an increment every slave integration point is
// projected onto the master in the converged configuration; the projection (master segment,
// shape functions, frame n, t1, t2) is then held fixed during the Newton iterations, so within
// an increment
//   g_N     = g_N0 + (du_s - sum_J N_J du_J) . n      (Eq. A11, linearised in the increment)
//   dg_T[k] = (sum_J N_J du_J - du_s) . t_k           (Eq. A13)
// are linear in the increment and the tangent is the exact derivative of the residual (the
// frame moves only between increments: small slip per increment). A point whose projection
// crosses a natural border is inactive for the increment.
//
// Forces: the contact's virtual work t_N dg_N + tau . dg_T gives the internal forces
//   slave node a:   N_a (t_N n - tau1 t1 - tau2 t2) w j,   master node J: the opposite with N_J,
// with t_N < 0 in compression. In 2D t2 = e3 and tau2 = dg_T[1] = 0. The traction's Jacobian
// columns are [0, D) the slave point's displacement and [D, 2D) the projected master point's
// (fem/mortar_kinematics.hpp).

#include <array>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "fem/mesh.hpp"
#include "fem/mortar_kinematics.hpp"
#include "fem/mortar_surface_2d.hpp"
#include "fem/mortar_surface_3d.hpp"

namespace ifsim::fem {

template <int D>
class MortarContact final : public MortarKinematics {
public:
    static_assert(D == 2 || D == 3);
    using Surface = std::conditional_t<D == 2, MortarSurface2D, MortarSurface3D>;
    static constexpr int face_nodes = D == 2 ? 2 : 4; // nodes of a slave or master segment

    MortarContact(const Mesh& mesh, const std::string& slave_faces,
                  const std::string& master_faces);

    int dim() const override { return D; }
    std::size_t n_points() const override { return points_.size(); }
    const ContactKinematics& point(std::size_t i) const override { return points_[i].k; }
    const ProjectionCounters& projection_counters() const override { return counters_; }

    // Projects every slave integration point in the configuration x + u (start of an
    // increment). Returns true when the pairing (active flags and master segments) changed.
    bool pair(const Mesh& mesh, const std::vector<double>& u) override;
    // Gaps of the active points for the displacement increment du (D per node).
    void update_gaps(const std::vector<double>& du) override;
    void assemble(std::span<const ContactTraction> traction, std::vector<double>& f_int,
                  std::vector<ContactTriplet>* K) const override;
    std::vector<std::array<int, 2>> couplings() const override;

    // The master edge (2D) or face (3D) point i projects onto; -1 when inactive.
    int master_segment(std::size_t i) const { return points_[i].master_segment; }
    const Surface& slave_surface() const { return slave_; }
    const Surface& master_surface() const { return master_; }

private:
    struct Point {
        ContactKinematics k; // what the contact pairs read: gaps, frame, slave element, weight
        double g_N0 = 0.0;   // normal gap at the start of the increment
        int master_segment = -1;
        std::array<int, face_nodes> slave_nodes{}, master_nodes{};
        std::array<double, face_nodes> slave_N{}, master_N{};
    };

    Surface slave_;
    Surface master_;
    std::vector<Point> points_;
    ProjectionCounters counters_;
};

extern template class MortarContact<2>;
extern template class MortarContact<3>;

} // namespace ifsim::fem
