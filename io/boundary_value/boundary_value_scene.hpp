#pragma once
// A scene of kind "boundary-value" (finite elements; docs/scenes.md): structured bodies merged
// into one mesh with a material per body, or a Gmsh mesh file with a material per region; the
// contact pairs ([interface] or [[contact]]) with their interface formulations, the solver
// settings, the output sets
// and the stages. Every key is checked at parse time, sets against the mesh and each stage's
// constraints against each other.

#include <map>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "fem/mesh.hpp"
#include "fem/solver_settings.hpp"
#include "fem/stage.hpp"
#include "io/boundary_value/boundary_value_contacts.hpp"
#include "io/boundary_value/boundary_value_material.hpp"
#include "io/boundary_value/boundary_value_mesh.hpp"
#include "io/boundary_value/boundary_value_recorders.hpp"
#include "io/boundary_value/field_schedule.hpp"
#include "io/scene/table_reader.hpp"

namespace ifsim::io {

// [output]: what history.csv measures.
struct BoundaryValueOutput {
    std::string plate;          // node set: "the plate"
    std::string soil_top;       // node set: the soil's top
    std::string traction_faces; // face set, runs without contact pairs only
    std::size_t contact = 0;    // [output] contact: index of the pair of the main columns
    FieldSchedule fields;       // [output] fields: VTU/PVD field output (off by default)
};

struct BoundaryValueScene {
    std::string description;
    MeshSpec mesh_spec;
    // The structured bodies, or with a mesh file its regions (named after their element sets).
    std::vector<BodySpec> bodies;
    std::map<std::string, BodyMaterial> materials; // by body name
    fem::Mesh mesh;
    fem::SolverSettings settings;
    std::string linear_solver;              // umfpack | klu
    std::string tangent;                    // perturbation | fixed-substeps | rate
    std::string predictor = "extrapolated"; // extrapolated | tangent | zero
    // [interface] (one pair, named "interface") or the [[contact]] entries, in order.
    std::vector<BoundaryValueInterface> contacts;
    BoundaryValueOutput output;
    Recorders recorders; // [[recorder]] entries
    std::vector<fem::Stage> stages;

    long total_steps() const;
    // The pair that history.csv's main contact columns describe; nullptr without contact.
    const BoundaryValueInterface* main_contact() const;
    // The solver's materials in body order.
    std::vector<fem::ElementSetMaterial> set_materials() const;
};

// A node set of the mesh named by the key's string. Throws SceneError listing the sets.
std::string read_node_set(const TableReader& t, std::string_view key, const fem::Mesh& mesh);

// Reads and checks the whole scene. Throws SceneError naming the file, the key and what was
// expected.
BoundaryValueScene read_boundary_value_scene(const toml::table& scene, const std::string& file);

} // namespace ifsim::io
