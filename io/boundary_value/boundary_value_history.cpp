#include "io/boundary_value/boundary_value_history.hpp"

#include <cmath>

#include "kernels/model_api.hpp"

namespace ifsim::io {

namespace {

// sigma n with a Voigt stress (tensor shear components).
Vec3 traction(const fem::Voigt6& s, const Vec3& n) {
    return {s[0] * n[0] + s[3] * n[1] + s[4] * n[2], s[3] * n[0] + s[1] * n[1] + s[5] * n[2],
            s[4] * n[0] + s[5] * n[1] + s[2] * n[2]};
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
        // The four columns every pair always had, then (added later, so appended: the older
        // columns keep their positions) the relative displacements and forces.
        for (const BoundaryValueInterface& c : scene.contacts) {
            for (const char* column : {"t_n", "t_t1", "t_t2", "closed_points"}) {
                out.push_back(c.pair.name + "." + column);
            }
        }
        for (const BoundaryValueInterface& c : scene.contacts) {
            for (const char* column : {"u_n", "u_t1", "u_t2", "F_n", "F_t1", "F_t2"}) {
                out.push_back(c.pair.name + "." + column);
            }
        }
    }
    for (const std::string& c : recorder_columns(scene.recorders)) {
        out.push_back(c);
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
    for (const PairTractions& p : r.pairs) {
        for (double v : {p.u_n, p.u_t1, p.u_t2, p.F_n, p.F_t1, p.F_t2}) {
            out.real(v);
        }
    }
    for (const auto& v : r.recorders) {
        optional_real(out, v);
    }
    out.end_row();
}

BoundaryValueProbe::BoundaryValueProbe(const BoundaryValueScene& scene)
    : scene_(scene), main_(scene.main_contact()), dim_(scene.mesh.dim()),
      faces_(main_ != nullptr ? main_->pair.slave_faces : scene.output.traction_faces),
      geometry_(face_set_geometry(scene.mesh, faces_)),
      plate_(scene.mesh.node_set(scene.output.plate)),
      soil_top_(scene.mesh.node_set(scene.output.soil_top)),
      face_nodes_(scene.mesh.nodes_of_faces(faces_)),
      recorders_(scene.recorders, scene.mesh, scene.contacts) {
    if (main_ != nullptr) {
        frame_ = pair_frame(scene.mesh, faces_, main_->pair.shear_direction);
    } else {
        frame_ = {geometry_.normal, {1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}};
    }
    if (scene.contacts.size() > 1) {
        for (const BoundaryValueInterface& c : scene.contacts) {
            pair_geometry_.push_back(face_set_geometry(scene.mesh, c.pair.slave_faces));
            pair_frames_.push_back(
                pair_frame(scene.mesh, c.pair.slave_faces, c.pair.shear_direction));
            pair_slave_nodes_.push_back(scene.mesh.nodes_of_faces(c.pair.slave_faces));
            pair_master_nodes_.push_back(scene.mesh.nodes_of_faces(c.pair.master_faces));
        }
    }
}

Vec3 BoundaryValueProbe::mean(const fem::StaticSolver& solver,
                              const std::vector<int>& nodes) const {
    const auto& u = solver.displacement();
    Vec3 out{};
    for (int d = 0; d < dim_; ++d) {
        double sum = 0.0;
        for (int n : nodes) {
            sum += u[static_cast<std::size_t>(n * dim_ + d)];
        }
        out[static_cast<std::size_t>(d)] =
            nodes.empty() ? 0.0 : sum / static_cast<double>(nodes.size());
    }
    return out;
}

void BoundaryValueProbe::measure(const fem::StaticSolver& solver, BoundaryValueRow& row) {
    row.recorders = recorders_.measure(solver);
    const Vec3 plate = mean(solver, plate_);
    const Vec3 top = mean(solver, soil_top_);
    if (main_ != nullptr) {
        // In the main pair's frame (a shear box with shear along +x: x, y and vertical).
        const Vec3 rel{plate[0] - top[0], plate[1] - top[1], plate[2] - top[2]};
        row.u_t1 = dot(rel, frame_.t1);
        row.u_t2 = dim_ == 3 ? dot(rel, frame_.t2) : 0.0;
        row.u_n = dot(rel, frame_.n) + 0.0; // + 0.0: never -0 in the file
        const auto& pairs = solver.contacts();
        if (scene_.contacts.size() > 1) {
            for (std::size_t k = 0; k < pairs.size(); ++k) {
                const fem::ContactResultant r = pairs[k]->resultant();
                const PairFrame& f = pair_frames_[k];
                PairTractions p;
                p.t_n = r.t_N;
                p.t_t1 = dot(r.shear, f.t1);
                p.t_t2 = dim_ == 3 ? dot(r.shear, f.t2) : 0.0;
                p.closed_points = r.closed;
                const Vec3 m = mean(solver, pair_master_nodes_[k]);
                const Vec3 sl = mean(solver, pair_slave_nodes_[k]);
                const Vec3 d{m[0] - sl[0], m[1] - sl[1], m[2] - sl[2]};
                p.u_n = dot(d, f.n) + 0.0;
                p.u_t1 = dot(d, f.t1) + 0.0;
                p.u_t2 = dim_ == 3 ? dot(d, f.t2) + 0.0 : 0.0;
                p.F_n = r.area * p.t_n;
                p.F_t1 = r.area * p.t_t1;
                p.F_t2 = r.area * p.t_t2;
                row.pairs.push_back(p);
            }
        }
        const fem::ContactResultant r = pairs.at(scene_.output.contact)->resultant();
        row.t_n = r.t_N;
        row.t_t1 = dot(r.shear, frame_.t1);
        row.t_t2 = dim_ == 3 ? dot(r.shear, frame_.t2) : 0.0;
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
    const int v = dim_ - 1;
    row.u_t1 = plate[0] - top[0];
    row.u_t2 = dim_ == 3 ? plate[1] - top[1] : 0.0;
    row.u_n = top[static_cast<std::size_t>(v)] - plate[static_cast<std::size_t>(v)];
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
                                                    const PairFrame& frame,
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
    const Vec3 shear{t[0] - out.t_n * n[0], t[1] - out.t_n * n[1], t[2] - out.t_n * n[2]};
    out.t_t1 = dot(shear, frame.t1);
    out.t_t2 = dim_ == 3 ? dot(shear, frame.t2) : 0.0;
    out.F_n = geometry.area * out.t_n;
    out.F_t1 = geometry.area * out.t_t1;
    out.F_t2 = geometry.area * out.t_t2;
    return out;
}

void BoundaryValueProbe::initial(const fem::StaticSolver& solver, BoundaryValueRow& row) const {
    row.recorders = recorders_.initial();
    fem::Voigt6 mean_stress{};
    const PairTractions main = initial_tractions(solver, faces_, geometry_, frame_, mean_stress);
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
                                              pair_geometry_[k], pair_frames_[k], unused));
    }
    const BoundaryValueInterface& bi = *main_;
    if (bi.formulation.is_coulomb()) {
        return;
    }
    // The interface's start in the contact's frame (sigma_p2 is a normal component: the sense
    // of t2 does not matter).
    const Vec3& n = geometry_.normal;
    const auto normal_of = [&](const Vec3& a) { return dot(a, traction(mean_stress, a)); };
    const fem::Voigt6 local{normal_of(n),
                            normal_of(frame_.t1),
                            normal_of(frame_.t2),
                            dot(frame_.t1, traction(mean_stress, n)),
                            dot(frame_.t2, traction(mean_stress, n)),
                            0.0};
    const std::vector<double> y = bi.pair.initial_state(local);
    row.s_p1 = y[1];
    row.s_p2 = y[2];
    row.eps_n = 0.0;
    row.band_thickness = bi.formulation.contact.interface.shear_band_thickness;
    row.e_interface = y[static_cast<std::size_t>(state_index::void_ratio)];
}

} // namespace ifsim::io
