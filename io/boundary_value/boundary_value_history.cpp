#include "io/boundary_value/boundary_value_history.hpp"

#include <cmath>

#include "kernels/model_api.hpp"

namespace ifsim::io {

namespace {

using Vec3 = std::array<double, 3>;

// sigma n with a Voigt stress (tensor shear components).
Vec3 traction(const fem::Voigt6& s, const Vec3& n) {
    return {s[0] * n[0] + s[3] * n[1] + s[4] * n[2], s[3] * n[0] + s[1] * n[1] + s[5] * n[2],
            s[4] * n[0] + s[5] * n[1] + s[2] * n[2]};
}

double dot(const Vec3& a, const Vec3& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

void optional_real(HistoryWriter& out, const std::optional<double>& v) {
    if (v) {
        out.real(*v);
    } else {
        out.empty();
    }
}

} // namespace

std::vector<std::string> boundary_value_history_columns(const BoundaryValueScene& scene) {
    std::vector<std::string> out = {"increment",      "stage",      "time", "newton_iterations",
                                    "u_t1",           "u_t2",       "u_n",  "t_n",
                                    "t_t1",           "t_t2",       "cuts", "residual",
                                    "closed_points",  "s_p1",       "s_p2", "eps_n",
                                    "band_thickness", "e_interface"};
    if (scene.contacts.size() > 1) {
        for (const BoundaryValueInterface& c : scene.contacts) {
            for (const char* column : {"t_n", "t_t1", "t_t2", "closed_points"}) {
                out.push_back(c.pair.name + "." + column);
            }
        }
    }
    return out;
}

void write_boundary_value_row(HistoryWriter& out, const BoundaryValueRow& r) {
    out.integer(r.increment);
    out.integer(r.stage);
    out.real(r.time);
    out.integer(r.newton_iterations);
    for (double v : {r.u_t1, r.u_t2, r.u_n, r.t_n, r.t_t1, r.t_t2}) {
        out.real(v);
    }
    out.integer(r.cuts);
    out.real(r.residual);
    if (r.closed_points) {
        out.integer(*r.closed_points);
    } else {
        out.empty();
    }
    for (const auto& v : {r.s_p1, r.s_p2, r.eps_n, r.band_thickness, r.e_interface}) {
        optional_real(out, v);
    }
    for (const PairTractions& p : r.pairs) {
        out.real(p.t_n);
        out.real(p.t_t1);
        out.real(p.t_t2);
        out.integer(p.closed_points);
    }
    out.end_row();
}

BoundaryValueProbe::BoundaryValueProbe(const BoundaryValueScene& scene)
    : scene_(scene), main_(scene.main_contact()), dim_(scene.mesh.dim()),
      faces_(main_ != nullptr ? main_->pair.slave_faces : scene.output.traction_faces),
      geometry_(face_set_geometry(scene.mesh, faces_)),
      plate_(scene.mesh.node_set(scene.output.plate)),
      soil_top_(scene.mesh.node_set(scene.output.soil_top)),
      face_nodes_(scene.mesh.nodes_of_faces(faces_)) {
    if (scene.contacts.size() > 1) {
        for (const BoundaryValueInterface& c : scene.contacts) {
            pair_geometry_.push_back(face_set_geometry(scene.mesh, c.pair.slave_faces));
        }
    }
}

double BoundaryValueProbe::mean(const fem::StaticSolver& solver, const std::vector<int>& nodes,
                                int d) const {
    const auto& u = solver.displacement();
    double sum = 0.0;
    for (int n : nodes) {
        sum += u[static_cast<std::size_t>(n * dim_ + d)];
    }
    return nodes.empty() ? 0.0 : sum / static_cast<double>(nodes.size());
}

void BoundaryValueProbe::measure(const fem::StaticSolver& solver, BoundaryValueRow& row) const {
    const int v = dim_ - 1;
    row.u_t1 = mean(solver, plate_, 0) - mean(solver, soil_top_, 0);
    row.u_t2 = dim_ == 3 ? mean(solver, plate_, 1) - mean(solver, soil_top_, 1) : 0.0;
    row.u_n = mean(solver, soil_top_, v) - mean(solver, plate_, v);
    if (main_ != nullptr) {
        const auto& pairs = solver.contacts();
        if (scene_.contacts.size() > 1) {
            for (const auto& p : pairs) {
                const fem::ContactResultant r = p->resultant();
                row.pairs.push_back({r.t_N, r.shear[0], dim_ == 3 ? r.shear[1] : 0.0, r.closed});
            }
        }
        const fem::ContactResultant r = pairs.at(scene_.output.contact)->resultant();
        row.t_n = r.t_N;
        row.t_t1 = r.shear[0];
        row.t_t2 = dim_ == 3 ? r.shear[1] : 0.0;
        row.closed_points = r.closed;
        if (!main_->formulation.is_coulomb()) {
            row.s_p1 = r.sigma_p1;
            row.s_p2 = r.sigma_p2;
            row.eps_n = r.eps_N;
            row.band_thickness = r.band_thickness;
            row.e_interface = r.void_ratio;
        }
        return;
    }
    // The reactions on the faces' nodes: the force the surroundings exert on the soil.
    const auto& f_int = solver.internal_force();
    const auto& f_ext = solver.external_force();
    Vec3 R{};
    for (int n : face_nodes_) {
        for (int d = 0; d < dim_; ++d) {
            const auto k = static_cast<std::size_t>(n * dim_ + d);
            R[static_cast<std::size_t>(d)] += f_int[k] - (f_ext.empty() ? 0.0 : f_ext[k]);
        }
    }
    const double A = geometry_.area;
    const Vec3& n = geometry_.normal;
    row.t_n = dot(R, n) / A;
    row.t_t1 = R[0] / A - row.t_n * n[0];
    row.t_t2 = dim_ == 3 ? R[1] / A - row.t_n * n[1] : 0.0;
}

PairTractions BoundaryValueProbe::initial_tractions(const fem::StaticSolver& solver,
                                                    const std::string& faces,
                                                    const FaceGeometry& geometry,
                                                    fem::Voigt6& mean_stress) const {
    // Area-weighted mean of sigma n over the faces, sigma the mean of each face's element.
    Vec3 t{};
    mean_stress = {};
    const int nip = solver.points_per_element();
    for (const fem::FaceRef& f : scene_.mesh.face_set(faces)) {
        fem::Voigt6 s{};
        for (int q = 0; q < nip; ++q) {
            const std::vector<double> y = solver.state(f.element, q);
            for (std::size_t j = 0; j < 6; ++j) {
                s[j] += y[j] / nip;
            }
        }
        const FaceGeometry g = face_geometry(scene_.mesh, f);
        const Vec3 tf = traction(s, g.normal);
        for (std::size_t d = 0; d < 3; ++d) {
            t[d] += g.area * tf[d] / geometry.area;
        }
        for (std::size_t j = 0; j < 6; ++j) {
            mean_stress[j] += g.area * s[j] / geometry.area;
        }
    }
    const Vec3& n = geometry.normal;
    PairTractions out;
    out.t_n = dot(t, n);
    out.t_t1 = t[0] - out.t_n * n[0];
    out.t_t2 = dim_ == 3 ? t[1] - out.t_n * n[1] : 0.0;
    return out;
}

void BoundaryValueProbe::initial(const fem::StaticSolver& solver, BoundaryValueRow& row) const {
    fem::Voigt6 mean_stress{};
    const PairTractions main = initial_tractions(solver, faces_, geometry_, mean_stress);
    row.t_n = main.t_n;
    row.t_t1 = main.t_t1;
    row.t_t2 = main.t_t2;
    if (main_ == nullptr) {
        return;
    }
    row.closed_points = 0;
    for (std::size_t k = 0; k < pair_geometry_.size(); ++k) {
        fem::Voigt6 unused{};
        row.pairs.push_back(initial_tractions(solver, scene_.contacts[k].pair.slave_faces,
                                              pair_geometry_[k], unused));
    }
    const BoundaryValueInterface& bi = *main_;
    if (bi.formulation.is_coulomb()) {
        return;
    }
    const Vec3& n = geometry_.normal;
    // The interface's start in the contact's frame: t1 along the shear direction in the plane.
    const auto& dir = bi.pair.shear_direction;
    Vec3 t1{dir[0], dir[1], dim_ == 2 ? 0.0 : dir[2]};
    const double dn = dot(t1, n);
    for (std::size_t d = 0; d < 3; ++d) {
        t1[d] -= dn * n[d];
    }
    const double len = std::sqrt(dot(t1, t1));
    for (double& c : t1) {
        c = len > 0.0 ? c / len : 0.0;
    }
    const Vec3 t2{n[1] * t1[2] - n[2] * t1[1], n[2] * t1[0] - n[0] * t1[2],
                  n[0] * t1[1] - n[1] * t1[0]};
    const auto normal_of = [&](const Vec3& a) { return dot(a, traction(mean_stress, a)); };
    const fem::Voigt6 local{normal_of(n),
                            normal_of(t1),
                            normal_of(t2),
                            dot(t1, traction(mean_stress, n)),
                            dot(t2, traction(mean_stress, n)),
                            0.0};
    const std::vector<double> y = bi.pair.initial_state(local);
    row.s_p1 = y[1];
    row.s_p2 = y[2];
    row.eps_n = 0.0;
    row.band_thickness = bi.formulation.contact.interface.shear_band_thickness;
    row.e_interface = y[static_cast<std::size_t>(state_index::void_ratio)];
}

} // namespace ifsim::io
