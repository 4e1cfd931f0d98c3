#include "fem/contact_set.hpp"

#include <algorithm>

namespace ifsim::fem {

void ContactSet::add(const Mesh& mesh, ContactPairSpec spec) {
    pairs_.push_back(make_contact_pair(mesh, std::move(spec)));
}

bool ContactSet::begin_increment(const Mesh& mesh, const std::vector<double>& u,
                                 const ElementStresses& committed) {
    bool changed = false;
    for (auto& c : pairs_) {
        changed = c->begin_increment(mesh, u, committed) || changed;
    }
    return changed;
}

std::vector<std::array<int, 2>> ContactSet::couplings() const {
    std::vector<std::array<int, 2>> all;
    for (const auto& c : pairs_) {
        const auto more = c->couplings();
        all.insert(all.end(), more.begin(), more.end());
    }
    return all;
}

bool ContactSet::evaluate(const std::vector<double>& du, std::vector<double>& f_int,
                          std::string& error) {
    for (auto& c : pairs_) {
        if (!c->evaluate(du, f_int, error)) {
            return false;
        }
    }
    return true;
}

double ContactSet::regather(const ElementStresses& trial) {
    double change = 0.0;
    for (auto& c : pairs_) {
        change = std::max(change, c->regather(trial));
    }
    return change;
}

void ContactSet::restore_targets() {
    for (auto& c : pairs_) {
        c->restore_targets();
    }
}

void ContactSet::relax_targets() {
    for (auto& c : pairs_) {
        c->relax_targets();
    }
}

std::size_t ContactSet::release_outgrown_partitions() {
    std::size_t n = 0;
    for (auto& c : pairs_) {
        n += c->release_outgrown_partitions();
    }
    return n;
}

void ContactSet::hold_chosen_partitions() {
    for (auto& c : pairs_) {
        c->hold_chosen_partitions();
    }
}

void ContactSet::commit() {
    for (auto& c : pairs_) {
        c->commit();
    }
}

std::size_t ContactSet::points() const {
    std::size_t n = 0;
    for (const auto& c : pairs_) {
        n += c->kinematics().n_points();
    }
    return n;
}

ContactSetCounters ContactSet::counters() const {
    ContactSetCounters s;
    for (const auto& c : pairs_) {
        const ContactPairCounters& k = c->counters();
        s.pairings += c->kinematics().projection_counters().pairings;
        s.evaluations += k.evaluations;
        s.point_updates += k.point_updates;
        s.lanes += k.lanes;
        s.subincrements += k.subincrements;
        s.constitutive_evaluations += k.constitutive_evaluations;
        s.model_substeps += k.model_substeps;
        s.interface_newton_iterations += k.interface_newton_iterations;
        s.failed_evaluations += k.failed_evaluations;
        s.relaxed_reruns += k.relaxed_reruns;
        s.relaxed_point_updates += k.relaxed_point_updates;
        s.viscous_point_updates += k.viscous_point_updates;
        s.viscous_share_max = std::max(s.viscous_share_max, k.viscous_share_max);
        s.viscous_traction_max = std::max(s.viscous_traction_max, k.viscous_traction_max);
        s.band_clamped += k.band_clamped;
        s.dropped_columns += k.dropped_columns;
        s.newton_fallbacks += k.newton_fallbacks;
    }
    return s;
}

ContactPairTimers ContactSet::timers() const {
    ContactPairTimers t;
    t.scatter = matrix_seconds_;
    for (const auto& c : pairs_) {
        t.search += c->timers().search;
        t.gather += c->timers().gather;
        t.kernels += c->timers().kernels;
        t.scatter += c->timers().scatter;
    }
    return t;
}

} // namespace ifsim::fem
