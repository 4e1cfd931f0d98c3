#pragma once
// The contact pairs of a model as one participant of the solver: pairing and gather at the
// start of an increment (and whether the sparse pattern must change), forces of a trial
// increment, tangent entries, the implicit re-gather of the in-plane targets, commit, and the
// pairs' counters and timers summed.

#include <algorithm>
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "fem/contact_pair.hpp"
#include "fem/mesh.hpp"
#include "fem/phase_timer.hpp"

namespace ifsim::fem {

// The pairs' counters summed, and their pairings.
struct ContactSetCounters : ContactPairCounters {
    long pairings = 0;
};

class ContactSet {
public:
    bool empty() const { return pairs_.empty(); }
    // Contact points of all pairs.
    std::size_t points() const;
    // Drops every pair's record of a failed point (ContactPair::last_failure).
    void forget_failures() {
        for (auto& p : pairs_) {
            p->forget_failure();
        }
    }
    void add(const Mesh& mesh, ContactPairSpec spec);
    const std::vector<std::unique_ptr<ContactPair>>& pairs() const { return pairs_; }

    // Pairs every contact at the committed displacement u and gathers its stresses; true when
    // a pairing changed the DOF couplings.
    bool begin_increment(const Mesh& mesh, const std::vector<double>& u,
                         const ElementStresses& committed);
    // The DOF pairs (row, column) of every pair's current pairing: extra pattern entries.
    std::vector<std::array<int, 2>> couplings() const;
    // Forces of the trial increment du added to f_int; false with the failed pair's message.
    bool evaluate(const std::vector<double>& du, std::vector<double>& f_int, std::string& error);
    // Every pair's tangent entries of its last evaluate(), each handed to add(row, col, value)
    // with global DOFs.
    template <typename Add>
    void add_tangent(Add add) {
        for (const auto& c : pairs_) {
            scratch_.clear();
            c->add_tangent(scratch_); // timed by the pair (kernels when its lanes were deferred)
            PhaseTimer timer(matrix_seconds_);
            for (const ContactTriplet& k : scratch_) {
                add(k.row, k.col, k.value);
            }
        }
    }
    // Implicit gather: the largest relative change of a target over the pairs.
    double regather(const ElementStresses& trial);
    // Back to the targets before the last regather.
    void restore_targets();
    // Aitken relaxation of the last regather's targets, pair by pair.
    void relax_targets();
    // Points over all pairs whose held sub-increments were released (ContactPair).
    std::size_t release_outgrown_partitions();
    void hold_chosen_partitions();
    void set_increment_length(double dt) {
        for (auto& c : pairs_) {
            c->set_increment_length(dt);
        }
    }
    bool viscous_fallback() const {
        return std::any_of(pairs_.begin(), pairs_.end(),
                           [](const auto& c) { return c->viscous_fallback(); });
    }
    void set_viscous_retry(bool on) {
        for (auto& c : pairs_) {
            c->set_viscous_retry(on);
        }
    }
    void commit();
    void set_probing(bool on) {
        for (auto& c : pairs_) {
            c->set_probing(on);
        }
    }

    ContactSetCounters counters() const;
    ContactPairTimers timers() const; // summed over the pairs

private:
    std::vector<std::unique_ptr<ContactPair>> pairs_;
    std::vector<ContactTriplet> scratch_;
    double matrix_seconds_ = 0.0; // adding the tangent entries to the matrix (scatter)
};

} // namespace ifsim::fem
