#include "fem/contact_coulomb.hpp"

namespace ifsim::fem {

namespace {

std::size_t n_slave_points(const Mesh& mesh, const std::string& faces) {
    return 2 * mesh.face_set(faces).size(); // 2-point Gauss per slave edge
}

} // namespace

CoulombContact2D::CoulombContact2D(const Mesh& mesh, CoulombContactSpec spec)
    : spec_(std::move(spec)), mortar_(mesh, spec_.slave_faces, spec_.master_faces),
      points_(n_slave_points(mesh, spec_.slave_faces), 2) {
    for (std::size_t i = 0; i < points_.size(); ++i) {
        points_.set_traction(i, 0.0, 0.0);
    }
}

bool CoulombContact2D::begin_increment(const Mesh& mesh, const std::vector<double>& u) {
    const bool changed = mortar_.pair(mesh, u);
    for (std::size_t i = 0; i < points_.size(); ++i) {
        const auto& pt = mortar_.points()[i];
        const double n[3] = {pt.master.normal[0], pt.master.normal[1], 0.0};
        const double t[3] = {pt.master.tangent[0], pt.master.tangent[1], 0.0};
        const double z[3] = {0.0, 0.0, 1.0};
        points_.set_frame(i, n, t, z);
    }
    return changed;
}

int CoulombContact2D::forces(const std::vector<double>& du, std::vector<double>& f_int,
                             std::vector<ContactTriplet>* K) {
    mortar_.update_gaps(du);
    int closed_points = 0;
    for (std::size_t i = 0; i < points_.size(); ++i) {
        const auto& pt = mortar_.points()[i];
        const bool closed = pt.master.in_contact && pt.g_N <= 0.0;
        closed_points += closed ? 1 : 0;
        points_.input(coulomb_col::t_N)[i] = closed ? spec_.normal_penalty * pt.g_N : 0.0;
        points_.input(coulomb_col::k_N)[i] = closed ? spec_.normal_penalty : 0.0;
        points_.input(coulomb_col::dg1)[i] = pt.master.in_contact ? pt.dg_T : 0.0;
        points_.input(coulomb_col::dg2)[i] = 0.0;
    }
    coulomb_contact_update(points_, spec_.friction, {});
    traction_.assign(points_.size(), {});
    for (std::size_t i = 0; i < points_.size(); ++i) {
        auto& tr = traction_[i];
        tr.t_N = points_.output(contact_col::traction)[i];
        tr.tau = points_.output(contact_col::traction + 1)[i];
        for (int c = 0; c < 4; ++c) {
            tr.jac[0][static_cast<std::size_t>(c)] = points_.jacobian(i, 0, c);
            tr.jac[1][static_cast<std::size_t>(c)] = points_.jacobian(i, 1, c);
        }
    }
    mortar_.assemble(traction_, f_int, K);
    return closed_points;
}

} // namespace ifsim::fem
