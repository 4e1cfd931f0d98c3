#pragma once
// The checkpoint of a run being resumed (`ifsim resume DIR`), of any scene kind, and the check
// that it fits the scene it is to continue — made before anything in DIR changes (a foreign
// but well-formed checkpoint is refused, not run into a truncated history).

#include <filesystem>
#include <string>

#include "io/boundary_value/boundary_value_checkpoint.hpp"
#include "io/boundary_value/boundary_value_scene.hpp"
#include "io/element_test/element_checkpoint.hpp"
#include "io/element_test/element_test_scene.hpp"
#include "io/interface_test/interface_checkpoint.hpp"
#include "io/interface_test/interface_test_scene.hpp"

namespace ifsim::io {

struct ResumedRun {
    std::string kind;
    BoundaryValueCheckpoint boundary_value;
    ElementTestCheckpoint element;
    InterfaceTestCheckpoint interface;

    // Reads DIR/checkpoint. Throws CheckpointError naming the file and the defect.
    explicit ResumedRun(const std::filesystem::path& dir);
    const RunCheckpointHeader& run() const;

    // Empty when the checkpoint fits the scene (stage and step within the stages, state
    // lengths of its models, the mesh's size, the field collections); else what does not.
    std::string mismatch(const ElementTestScene& s) const;
    std::string mismatch(const InterfaceTestScene& s) const;
    std::string mismatch(const BoundaryValueScene& s) const;
};

} // namespace ifsim::io
