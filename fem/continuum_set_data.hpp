#pragma once
// ContinuumAssembly's data of one element set (shared by continuum_assembly.cpp and the
// updated-Lagrangian passes in continuum_assembly_ul.cpp; not part of fem's interface).

#include <array>
#include <memory>
#include <vector>

#include "fem/continuum_assembly.hpp"

namespace ifsim::fem {

struct ContinuumAssembly::SetData {
    ElementSetMaterial spec;
    std::unique_ptr<SetMaterial> material;
    std::vector<int> elements;
    std::vector<double> tangent;        // point * nc * nc
    std::array<double*, 6> deps_cols{}; // stable: the increment columns are never swapped
    std::vector<double> rotations;      // updated Lagrangian: R of each point (9, row-major)
};

} // namespace ifsim::fem
