#include "io/boundary_value/boundary_value_fields.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "engine/model_registry.hpp"
#include "io/boundary_value/boundary_value_scene.hpp"
#include "io/boundary_value/pair_frame.hpp"
#include "io/output/run_clock.hpp"

namespace ifsim::io {
namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

// ParaView reads a 6-component array as a symmetric tensor XX YY ZZ XY YZ XZ; ifsim's Voigt
// order is 11 22 33 12 13 23.
constexpr std::array<int, 6> vtk_from_voigt{0, 1, 2, 3, 5, 4};
const std::vector<std::string> tensor_components{"11", "22", "33", "12", "23", "13"};

void push_tensor(std::vector<double>& out, const double* voigt) {
    for (int c : vtk_from_voigt) {
        out.push_back(voigt[c]);
    }
}

// The field names of the model state blocks (six entries each, after stress and void ratio).
std::string block_name(std::string_view prefix) {
    if (prefix == "h") {
        return "intergranular_strain";
    }
    if (prefix == "a") {
        return "back_stress";
    }
    if (prefix == "z") {
        return "fabric";
    }
    if (prefix == "ain") {
        return "back_stress_at_reversal";
    }
    return fmt::format("state_{}", prefix);
}

std::string file_stem(long increment) {
    return fmt::format("{:06d}", increment);
}

} // namespace

FieldOutput::FieldOutput(const BoundaryValueScene& scene, const std::filesystem::path& dir)
    : schedule_(scene.output.fields), dir_(dir) {
    std::sort(schedule_.times.begin(), schedule_.times.end());
    std::filesystem::create_directories(dir_ / "fields");
    const fem::Mesh& mesh = scene.mesh;
    element_material_.assign(static_cast<std::size_t>(mesh.n_elements()), -1);
    element_model_.assign(element_material_.size(), "");
    element_blocks_.assign(element_material_.size(), {});
    for (const BodySpec& body : scene.bodies) {
        const BodyMaterial& m = scene.materials.at(body.name);
        auto it = std::find(material_names_.begin(), material_names_.end(), body.material);
        if (it == material_names_.end()) {
            material_names_.push_back(body.material);
            it = material_names_.end() - 1;
        }
        const int id = static_cast<int>(it - material_names_.begin());
        std::vector<std::string> blocks;
        for (std::string_view p : history_prefixes(m.set.material)) {
            blocks.push_back(block_name(p));
            if (std::find(block_names_.begin(), block_names_.end(), blocks.back()) ==
                block_names_.end()) {
                block_names_.push_back(blocks.back());
            }
        }
        for (int e : mesh.element_set(m.set.element_set)) {
            const auto k = static_cast<std::size_t>(e);
            element_material_[k] = id;
            element_model_[k] = m.spec.model;
            element_blocks_[k] = blocks;
        }
    }
    mesh_pvd_ = std::make_unique<PvdCollection>(dir_ / "mesh.pvd");
    for (const BoundaryValueInterface& c : scene.contacts) {
        contact_names_.push_back(c.pair.name);
        contact_pvd_.push_back(
            std::make_unique<PvdCollection>(dir_ / fmt::format("contact-{}.pvd", c.pair.name)));
    }
}

bool FieldOutput::due(long increment, double time, bool stage_end) {
    bool due = increment == 0 || (schedule_.stages && stage_end) ||
               (schedule_.every > 0 && increment % schedule_.every == 0);
    // A named time is written at the first increment that reaches it (a cut increment need
    // not end on it exactly); each named time once.
    const double slack = 1.0e-12 * std::max(1.0, std::abs(time));
    while (next_time_ < schedule_.times.size() && schedule_.times[next_time_] <= time + slack) {
        due = true;
        ++next_time_;
    }
    return due;
}

FieldOutputState FieldOutput::state() const {
    FieldOutputState out;
    out.present = true;
    out.next_time = next_time_;
    out.outputs = outputs_;
    out.collections.push_back(mesh_pvd_->entries());
    for (const auto& p : contact_pvd_) {
        out.collections.push_back(p->entries());
    }
    return out;
}

void FieldOutput::restore(const FieldOutputState& state) {
    if (!state.present || state.collections.size() != contact_pvd_.size() + 1 ||
        state.next_time > schedule_.times.size()) {
        throw std::runtime_error("the checkpoint's field collections do not fit the scene");
    }
    next_time_ = state.next_time;
    outputs_ = state.outputs;
    mesh_pvd_->restore(state.collections[0]);
    for (std::size_t k = 0; k < contact_pvd_.size(); ++k) {
        contact_pvd_[k]->restore(state.collections[k + 1]);
    }
}

void FieldOutput::flush() const {
    mesh_pvd_->flush();
    for (const auto& p : contact_pvd_) {
        p->flush();
    }
}

std::vector<double> FieldOutput::unreached_times() const {
    return {schedule_.times.begin() + static_cast<long>(next_time_), schedule_.times.end()};
}

std::vector<std::string> FieldOutput::collections() const {
    std::vector<std::string> out{mesh_pvd_->path().filename().string()};
    for (const auto& p : contact_pvd_) {
        out.push_back(p->path().filename().string());
    }
    return out;
}

void FieldOutput::write(const fem::StaticSolver& solver, long increment, double time) {
    const auto t0 = Clock::now();
    const std::string mesh_file = fmt::format("fields/mesh-{}.vtu", file_stem(increment));
    write_vtu(dir_ / mesh_file, mesh_grid(solver));
    mesh_pvd_->add(time, mesh_file);
    const auto& pairs = solver.contacts();
    for (std::size_t k = 0; k < pairs.size() && k < contact_pvd_.size(); ++k) {
        if (pairs[k]->kinematics().n_points() == 0) {
            continue; // not paired yet: the pairs are paired at the first increment's start
        }
        const std::string file =
            fmt::format("fields/contact-{}-{}.vtu", contact_names_[k], file_stem(increment));
        write_vtu(dir_ / file, contact_grid(solver, *pairs[k]));
        contact_pvd_[k]->add(time, file);
    }
    ++outputs_;
    seconds_ += since(t0);
}

VtuGrid FieldOutput::mesh_grid(const fem::StaticSolver& solver) const {
    const fem::Mesh& mesh = solver.mesh();
    const int D = mesh.dim();
    const int nen = mesh.nodes_per_element();
    const auto n_nodes = static_cast<std::size_t>(mesh.n_nodes());
    const auto n_el = static_cast<std::size_t>(mesh.n_elements());
    const std::vector<double>& u = solver.displacement();
    VtuGrid g;
    g.points.reserve(3 * n_nodes);
    for (std::size_t a = 0; a < n_nodes; ++a) {
        for (int i = 0; i < 3; ++i) {
            g.points.push_back(i < D ? mesh.coordinates[a * D + i] : 0.0);
        }
    }
    const std::uint8_t type =
        mesh.type == fem::ElementType::quad4 ? vtk_cell::quad : vtk_cell::hexahedron;
    for (std::size_t e = 0; e < n_el; ++e) {
        for (int a = 0; a < nen; ++a) {
            g.connectivity.push_back(mesh.node(static_cast<int>(e), a));
        }
        g.offsets.push_back(static_cast<std::int64_t>(g.connectivity.size()));
        g.types.push_back(type);
    }

    VtuArray disp{"displacement", 3, {}, {}};
    disp.values.reserve(3 * n_nodes);
    for (std::size_t a = 0; a < n_nodes; ++a) {
        for (int i = 0; i < 3; ++i) {
            disp.values.push_back(i < D ? u[a * D + i] : 0.0);
        }
    }

    // Per element: the mean over its integration points of stress, void ratio and state.
    const int nip = solver.points_per_element();
    VtuArray stress{"stress", 6, {}, tensor_components};
    VtuArray void_ratio{"void_ratio", 1, {}, {}};
    VtuArray material{"material", 1, {}, {}};
    std::vector<VtuArray> blocks;
    for (const std::string& b : block_names_) {
        blocks.push_back({b, 6, {}, tensor_components});
    }
    std::vector<std::array<double, 6>> element_stress(n_el);
    for (std::size_t e = 0; e < n_el; ++e) {
        std::vector<double> mean;
        for (int p = 0; p < nip; ++p) {
            const std::vector<double> y = solver.state(static_cast<int>(e), p);
            mean.resize(y.size(), 0.0);
            for (std::size_t k = 0; k < y.size(); ++k) {
                mean[k] += y[k] / nip;
            }
        }
        std::copy_n(mean.begin(), 6, element_stress[e].begin());
        push_tensor(stress.values, mean.data());
        void_ratio.values.push_back(mean.size() > static_cast<std::size_t>(state_index::void_ratio)
                                        ? mean[state_index::void_ratio]
                                        : nan);
        material.values.push_back(element_material_[e]);
        for (std::size_t b = 0; b < block_names_.size(); ++b) {
            const auto& own = element_blocks_[e];
            const auto at = std::find(own.begin(), own.end(), block_names_[b]);
            if (at == own.end()) {
                blocks[b].values.insert(blocks[b].values.end(), 6, nan);
                continue;
            }
            const auto first =
                static_cast<std::size_t>(state_index::model + 6 * (at - own.begin()));
            push_tensor(blocks[b].values, mean.data() + first);
        }
    }

    // Nodal average of the element means, for contour plots.
    VtuArray nodal{"stress_nodal", 6, std::vector<double>(6 * n_nodes, 0.0), tensor_components};
    std::vector<int> count(n_nodes, 0);
    for (std::size_t e = 0; e < n_el; ++e) {
        for (int a = 0; a < nen; ++a) {
            const auto node = static_cast<std::size_t>(mesh.node(static_cast<int>(e), a));
            ++count[node];
            for (int c = 0; c < 6; ++c) {
                nodal.values[6 * node + static_cast<std::size_t>(c)] +=
                    element_stress[e][static_cast<std::size_t>(vtk_from_voigt[c])];
            }
        }
    }
    for (std::size_t a = 0; a < n_nodes; ++a) {
        for (int c = 0; c < 6; ++c) {
            nodal.values[6 * a + static_cast<std::size_t>(c)] /= std::max(1, count[a]);
        }
    }

    g.point_data = {std::move(disp), std::move(nodal)};
    g.cell_data = {std::move(stress), std::move(void_ratio), std::move(material)};
    for (VtuArray& b : blocks) {
        g.cell_data.push_back(std::move(b));
    }
    return g;
}

VtuGrid FieldOutput::contact_grid(const fem::StaticSolver& solver,
                                  const fem::ContactPair& pair) const {
    const fem::Mesh& mesh = solver.mesh();
    const std::vector<double>& u = solver.displacement();
    const std::vector<fem::ContactPointRecord> records = pair.point_records();
    VtuGrid g;
    VtuArray disp{"displacement", 3, {}, {}};
    VtuArray t_N{"t_N", 1, {}, {}};
    VtuArray shear{"shear_traction", 3, {}, {}};
    VtuArray weight{"area", 1, {}, {}};
    VtuArray active{"active", 1, {}, {}};
    VtuArray open{"open", 1, {}, {}};
    VtuArray slipping{"slipping", 1, {}, {}};
    VtuArray sp1{"sigma_p1", 1, {}, {}}, sp2{"sigma_p2", 1, {}, {}};
    VtuArray eN{"eps_N", 1, {}, {}}, ep1{"eps_p1", 1, {}, {}}, ep2{"eps_p2", 1, {}, {}};
    VtuArray ds{"band_thickness", 1, {}, {}}, e{"void_ratio", 1, {}, {}};
    VtuArray sub{"subincrements", 1, {}, {}};
    for (std::size_t i = 0; i < records.size(); ++i) {
        const fem::ContactPointRecord& r = records[i];
        // Reference position and displacement of the slave point (shape functions of its
        // element), so that the points sit on the mesh file's surface.
        const Vec3 x = contact_point_position(mesh, r);
        const Vec3 ux = contact_point_position(mesh, r, u.data());
        g.points.insert(g.points.end(), x.begin(), x.end());
        g.connectivity.push_back(static_cast<std::int64_t>(i));
        g.offsets.push_back(static_cast<std::int64_t>(i + 1));
        g.types.push_back(vtk_cell::vertex);
        disp.values.insert(disp.values.end(), ux.begin(), ux.end());
        t_N.values.push_back(r.t_N);
        shear.values.insert(shear.values.end(), r.shear.begin(), r.shear.end());
        weight.values.push_back(r.weight);
        active.values.push_back(r.active ? 1.0 : 0.0);
        open.values.push_back(r.open);
        slipping.values.push_back(r.slipping);
        sp1.values.push_back(r.sigma_p1);
        sp2.values.push_back(r.sigma_p2);
        eN.values.push_back(r.eps_N);
        ep1.values.push_back(r.eps_p1);
        ep2.values.push_back(r.eps_p2);
        ds.values.push_back(r.band_thickness);
        e.values.push_back(r.void_ratio);
        sub.values.push_back(r.subincrements);
    }
    g.point_data = {std::move(disp),   std::move(t_N),    std::move(shear),
                    std::move(weight), std::move(active), std::move(open)};
    if (pair.spec().coulomb()) {
        g.point_data.push_back(std::move(slipping));
    } else {
        for (VtuArray* a : {&sp1, &sp2, &eN, &ep1, &ep2, &ds, &e, &sub}) {
            g.point_data.push_back(std::move(*a));
        }
    }
    return g;
}

} // namespace ifsim::io
