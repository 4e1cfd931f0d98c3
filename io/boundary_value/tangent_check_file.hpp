#pragma once
// tangent-check.csv: the records of [solver] check_tangent (fem/tangent_check.cpp), one row
// per Newton iteration and step size.

#include <filesystem>

#include "fem/static_solver.hpp"

namespace ifsim::io {

// Writes DIR/tangent-check.csv; throws std::runtime_error naming the file when it cannot.
void write_tangent_checks(const std::filesystem::path& dir, const fem::StaticSolver& solver);

} // namespace ifsim::io
