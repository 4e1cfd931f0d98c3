#include "io/cli/resumed_run.hpp"

#include <fmt/format.h>

#include "engine/contact_points.hpp"

namespace ifsim::io {
namespace {

// A position after step `step_in_stage` of 0-based `stage`.
template <class Stages>
std::string stage_mismatch(const Stages& stages, int stage, int step_in_stage) {
    if (stage < 0 || static_cast<std::size_t>(stage) >= stages.size()) {
        return fmt::format("its stage {} is not one of the scene's {} stages", stage + 1,
                           stages.size());
    }
    const int steps = stages[static_cast<std::size_t>(stage)].steps;
    if (step_in_stage < 1 || step_in_stage > steps) {
        return fmt::format("its step {} is not one of stage {}'s {} steps", step_in_stage,
                           stage + 1, steps);
    }
    return {};
}

std::string length_mismatch(const char* what, std::size_t have, std::size_t want) {
    return have == want ? std::string()
                        : fmt::format("its {} has {} values, the scene's {}", what, have, want);
}

} // namespace

ResumedRun::ResumedRun(const std::filesystem::path& dir) : kind(checkpoint_kind(dir)) {
    if (kind == "boundary-value") {
        boundary_value = read_boundary_value_checkpoint(dir);
    } else if (kind == "element-test") {
        element = read_element_test_checkpoint(dir);
    } else if (kind == "interface-test") {
        interface = read_interface_test_checkpoint(dir);
    } else {
        throw CheckpointError(fmt::format("{}: a checkpoint of an unknown kind \"{}\"",
                                          (dir / checkpoint_file_name).string(), kind));
    }
}

const RunCheckpointHeader& ResumedRun::run() const {
    return kind == "boundary-value" ? boundary_value.run
           : kind == "element-test" ? element.run
                                    : interface.run;
}

std::string ResumedRun::mismatch(const ElementTestScene& s) const {
    const ElementTestPosition& p = element.position;
    std::string why = stage_mismatch(s.stages, p.stage, p.step_in_stage);
    if (why.empty()) {
        why = length_mismatch("material state", p.state.size(), s.initial_state.size());
    }
    return why;
}

std::string ResumedRun::mismatch(const InterfaceTestScene& s) const {
    const InterfaceTestPosition& p = interface.position;
    std::string why = stage_mismatch(s.spec.stages, p.stage, p.step_in_stage);
    if (why.empty()) {
        why = length_mismatch("sample state", p.sample_state.size(), s.spec.sample_state.size());
    }
    if (why.empty()) {
        const std::size_t want = s.coulomb() ? 2
                                             : s.spec.interface_state.size() +
                                                   static_cast<std::size_t>(contact_state::n_extra);
        why = length_mismatch("interface state", p.interface_state.size(), want);
    }
    return why;
}

std::string ResumedRun::mismatch(const BoundaryValueScene& s) const {
    const BoundaryValueCheckpoint& c = boundary_value;
    if (c.stage_index >= s.stages.size()) {
        return fmt::format("its stage {} is not one of the scene's {} stages", c.stage_index + 1,
                           s.stages.size());
    }
    std::string why = length_mismatch("displacement", c.snapshot.u.size(),
                                      static_cast<std::size_t>(s.mesh.n_nodes()) *
                                          static_cast<std::size_t>(s.mesh.dim()));
    if (why.empty()) {
        why = length_mismatch("contact pairs", c.snapshot.contacts.size(), s.contacts.size());
    }
    if (why.empty() && c.fields.present != s.output.fields.enabled()) {
        why = c.fields.present ? "it has field collections, the scene writes no fields"
                               : "it has no field collections, the scene writes fields";
    }
    if (why.empty() && c.fields.present) {
        why = length_mismatch("field collections", c.fields.collections.size(),
                              s.contacts.size() + 1);
    }
    return why;
}

} // namespace ifsim::io
