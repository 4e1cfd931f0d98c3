#pragma once
// Field output of a boundary-value run ([output] fields, --fields; docs/scenes.md "Fields"):
// at chosen increments one VTK UnstructuredGrid of the mesh (nodal displacement and averaged
// stress; per element the mean stress over its integration points, void ratio, the model's
// state, the material) and one of each contact pair's points (tractions, the interface band's
// stresses and strains, open/closed, Algorithm 1 sub-increments), each series listed with its
// times in a ParaView collection (.pvd). A run without fields builds none of this.

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "fem/static_solver.hpp"
#include "io/boundary_value/field_schedule.hpp"
#include "io/output/vtu_writer.hpp"

namespace ifsim::io {

struct BoundaryValueScene;

// What a field output has written so far: carried by a checkpoint so that a resumed run
// continues the collections.
struct FieldOutputState {
    bool present = false;                                       // the run writes fields
    std::size_t next_time = 0;                                  // first named time not yet written
    std::size_t outputs = 0;                                    // output times written
    std::vector<std::vector<PvdCollection::Entry>> collections; // mesh, then each pair
};

class FieldOutput {
public:
    // Prepares DIR/fields/ and the collections DIR/mesh.pvd and DIR/contact-<pair>.pvd.
    FieldOutput(const BoundaryValueScene& scene, const std::filesystem::path& dir);

    // Whether the increment that ends at `time` (stage_end: the last of its stage) is due.
    bool due(long increment, double time, bool stage_end);
    // Writes the committed state of the solver as output number `increment` at `time`.
    void write(const fem::StaticSolver& solver, long increment, double time);

    FieldOutputState state() const;
    // Continues from a checkpoint's state. Throws std::runtime_error when it does not fit the
    // scene's collections.
    void restore(const FieldOutputState& state);

    // Rewrites the collections (at stage ends and at the end of the run).
    void flush() const;
    // Named times no increment reached (the run ended before them).
    std::vector<double> unreached_times() const;
    std::size_t outputs() const { return outputs_; }
    double seconds() const { return seconds_; }
    // Files relative to the run folder (the collections), for summary.json.
    std::vector<std::string> collections() const;
    const std::vector<std::string>& material_names() const { return material_names_; }

private:
    VtuGrid mesh_grid(const fem::StaticSolver& solver) const;
    VtuGrid contact_grid(const fem::StaticSolver& solver, const fem::ContactPair& pair) const;

    FieldSchedule schedule_;
    std::filesystem::path dir_;
    std::size_t next_time_ = 0; // first named time not yet written
    std::vector<std::string> material_names_;
    std::vector<int> element_material_;                    // index into material_names_
    std::vector<std::string> element_model_;               // model name per element
    std::vector<std::vector<std::string>> element_blocks_; // state block names per element
    std::vector<std::string> block_names_;                 // every state block of the run, in order
    std::unique_ptr<PvdCollection> mesh_pvd_;
    std::vector<std::unique_ptr<PvdCollection>> contact_pvd_;
    std::vector<std::string> contact_names_;
    std::size_t outputs_ = 0;
    double seconds_ = 0.0;
};

} // namespace ifsim::io
