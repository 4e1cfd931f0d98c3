// StaticSolver: the committed state as a snapshot, and a run continued from one
// (checkpoints). Bit for bit: tests/fem/test_snapshot.cpp.
#include <stdexcept>

#include "fem/static_solver.hpp"

namespace ifsim::fem {

SolverSnapshot StaticSolver::snapshot() const {
    SolverSnapshot s;
    s.stage_count = stage_count_;
    s.u = u_;
    s.u_stage_start = u_stage_start_;
    s.du_last = du_last_;
    s.f_int_committed = f_int_committed_;
    s.f_ext_committed = f_ext_committed_;
    s.dt_last = dt_last_;
    s.reference_sum = reference_sum_;
    s.committed_references = committed_references_;
    s.material_states = continuum_->committed_states();
    for (const auto& c : contacts_.pairs()) {
        s.contacts.push_back(c->snapshot());
    }
    s.spring_references = loads_.spring_references();
    s.imbalance = imbalance_;
    return s;
}

void StaticSolver::restore(const Stage& stage, const SolverSnapshot& s) {
    if (s.contacts.size() != contacts_.pairs().size() || s.u.size() != u_.size()) {
        throw std::invalid_argument("snapshot of another model: the number of DOFs or of "
                                    "contact pairs differs");
    }
    continuum_->restore_committed_states(s.material_states);
    // The pairs first (their first pairing must not initialise them again), then the stage
    // as its start prepared it, then the pairs once more (the stage start's pairing moved
    // their per-increment relaxation on).
    for (std::size_t k = 0; k < s.contacts.size(); ++k) {
        contacts_.pairs()[k]->restore(s.contacts[k]);
    }
    stage_count_ = s.stage_count - 1;
    u_ = s.u_stage_start;
    begin_stage(stage);
    for (std::size_t k = 0; k < s.contacts.size(); ++k) {
        contacts_.pairs()[k]->restore(s.contacts[k]);
    }
    loads_.set_spring_references(s.spring_references);
    u_ = s.u;
    du_last_ = s.du_last;
    dt_last_ = s.dt_last;
    f_int_committed_ = s.f_int_committed;
    f_ext_committed_ = s.f_ext_committed;
    reference_sum_ = s.reference_sum;
    committed_references_ = s.committed_references;
    imbalance_ = s.imbalance;
}

} // namespace ifsim::fem
