#pragma once
// The [interface] table of a boundary-value scene: one contact pair, soil side (slave faces)
// against structure (master faces), named "interface"; each [[contact]] entry
// (boundary_value_contacts.hpp) is the same table with a name. Keys: every formulation key of
// the interface-test [interface] table (read_interface_formulation, same meaning and defaults)
// plus
//
//   slave, master      face sets ("soil.bottom", "plate.top")
//   normal_penalty     k_N in kPa/m (default 1e8)
//   initial_contact    prestressed (default: t_N starts equal to the soil's normal stress) |
//                      geometric (t_N from the geometric gap alone)
//   shear_direction    3 numbers, global axes: the local t1 follows it (default [1, 0, 0])
//   void_ratio, intergranular_strain, back_stress, fabric
//                      the interface zone's state in LOCAL axes (11 = normal, 12 = n-t1,
//                      13 = n-t2); void_ratio defaults to the slave body's material's.
//
// The interface state of each contact point is built when the solver first pairs it, from the
// continuum stress there in local axes (initial_interface_stress: novel and Stutz from the
// continuum take sigma_N and the in-plane stresses from it, Stutz from the normal contact all
// three normal components equal to sigma_N) and model_state. The keys are checked at parse time
// by building the state once from the slave body's initial stress.

#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "fem/contact_pair.hpp"
#include "fem/mesh.hpp"
#include "io/boundary_value/boundary_value_material.hpp"
#include "io/scene/interface_formulation_reader.hpp"
#include "io/scene/table_reader.hpp"

namespace ifsim::io {

struct BoundaryValueInterface {
    InterfaceFormulationSpec formulation;
    std::string initial_contact; // prestressed | geometric
    std::string slave_body;      // the body whose faces are the slave
    fem::ContactPairSpec pair;   // ready for StaticSolver::add_contact
};

// The keys of the [interface] table (a [[contact]] entry has these and its name).
const std::vector<std::string_view>& boundary_value_interface_keys();

// The [interface] table: checks its keys, the pair is named "interface".
// `materials`: each body's material by body name. Throws SceneError.
BoundaryValueInterface
read_boundary_value_interface(const TableReader& interface, const fem::Mesh& mesh,
                              const std::map<std::string, BodyMaterial>& materials);

// A pair's keys of a table whose keys the caller has checked; the pair is named `name`.
BoundaryValueInterface
read_boundary_value_pair(const TableReader& table, const std::string& name, const fem::Mesh& mesh,
                         const std::map<std::string, BodyMaterial>& materials);

} // namespace ifsim::io
