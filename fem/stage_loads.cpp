#include "fem/stage_loads.hpp"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

#include "fem/loads.hpp"
#include "fem/phase_timer.hpp"

namespace ifsim::fem {

void StageLoads::check(const Mesh& mesh, const Stage& stage) {
    for (const GroundSpring& g : stage.springs) {
        if (g.direction < 0 || g.direction >= mesh.dim()) {
            throw std::invalid_argument(
                fmt::format("spring direction {} on node set '{}' does not exist in {}D",
                            g.direction, g.node_set, mesh.dim()));
        }
        mesh.node_set(g.node_set);
    }
    for (const FacePressure& p : stage.pressures) {
        mesh.face_set(p.face_set);
    }
}

void StageLoads::set_spring_references(const std::vector<std::vector<double>>& references) {
    if (references.size() != springs_.size()) {
        throw std::invalid_argument("snapshot of another stage: the number of springs differs");
    }
    for (std::size_t k = 0; k < springs_.size(); ++k) {
        if (references[k].size() != springs_[k].reference.size()) {
            throw std::invalid_argument("snapshot of another stage: a spring's nodes differ");
        }
        springs_[k].reference = references[k];
    }
}

void StageLoads::begin(const Mesh& mesh, const Stage& stage, std::span<const double> u,
                       const std::vector<double>& densities) {
    stage_ = stage;
    const int D = mesh.dim();
    std::vector<Spring> springs;
    for (const GroundSpring& g : stage.springs) {
        const auto& nodes = mesh.node_set(g.node_set);
        Spring sp;
        sp.key = fmt::format("{}#{}", g.node_set, g.direction);
        sp.stiffness = nodes.empty() ? 0.0 : g.total_stiffness / double(nodes.size());
        for (int n : nodes) {
            sp.dofs.push_back(n * D + g.direction);
        }
        const auto prev = std::find_if(springs_.begin(), springs_.end(),
                                       [&](const Spring& o) { return o.key == sp.key; });
        if (prev != springs_.end()) {
            sp.reference = prev->reference; // the spring continues from the previous stage
        } else {
            for (int d : sp.dofs) {
                sp.reference.push_back(u[static_cast<std::size_t>(d)]);
            }
        }
        springs.push_back(std::move(sp));
    }
    springs_ = std::move(springs);

    if (stage.gravity && gravity_unit_.empty()) {
        PhaseTimer timer(timers_.gravity);
        gravity_unit_ = unit_gravity_forces(mesh, densities);
        ++counters_.gravity_load_builds;
    }
    for (const FacePressure& p : stage.pressures) {
        if (!pressure_unit_.contains(p.face_set)) {
            PhaseTimer timer(timers_.pressure);
            pressure_unit_[p.face_set] = unit_pressure_forces(mesh, p.face_set);
            ++counters_.pressure_load_builds;
        }
    }
}

void StageLoads::external_force(double t, std::vector<double>& f) {
    std::fill(f.begin(), f.end(), 0.0);
    if (stage_.gravity) {
        PhaseTimer timer(timers_.gravity);
        const double g = stage_.gravity->from + (stage_.gravity->to - stage_.gravity->from) * t;
        for (std::size_t d = 0; d < f.size(); ++d) {
            f[d] += g * gravity_unit_[d];
        }
        ++counters_.gravity_load_applications;
    }
    if (!stage_.pressures.empty()) {
        PhaseTimer timer(timers_.pressure);
        for (const FacePressure& p : stage_.pressures) {
            const double v = p.from + (p.to - p.from) * t;
            const auto& unit = pressure_unit_.at(p.face_set);
            for (std::size_t d = 0; d < f.size(); ++d) {
                f[d] += v * unit[d];
            }
        }
    }
}

void StageLoads::add_spring_forces(std::span<const double> u, std::span<const double> du,
                                   std::vector<double>& f_int) const {
    for (const Spring& sp : springs_) {
        for (std::size_t k = 0; k < sp.dofs.size(); ++k) {
            const auto d = static_cast<std::size_t>(sp.dofs[k]);
            f_int[d] += sp.stiffness * (u[d] + du[d] - sp.reference[k]);
        }
    }
}

} // namespace ifsim::fem
