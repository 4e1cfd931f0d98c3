#pragma once
// The global tangent in compressed-column storage (Eigen::SparseMatrix<double>, int indices)
// with its pattern built once per DOF map from the elements' equation connectivity; each
// Newton iteration only zeroes and refills the values (no reallocation). Every element keeps
// the positions of its entries in the value array, so scattering an element matrix is a
// plain indexed add.
//
// Elements are coloured so that no two elements of one colour share a node or an equation
// (equal-displacement sets make elements far apart share the master's equation); a colour is
// scattered in parallel without locks, colours one after another, so every sum is formed in
// the same order for any number of threads.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/SparseCore>

#include "fem/dof_map.hpp"
#include "fem/mesh.hpp"

namespace ifsim::fem {

class SparseSystem {
public:
    // `couplings` are extra pairs of global DOFs (row, column) that get an entry, e.g. those
    // of the current contact pairing; pairs with a prescribed DOF are skipped.
    SparseSystem(const Mesh& mesh, const DofMap& dofs,
                 std::span<const std::array<int, 2>> couplings = {});

    Eigen::SparseMatrix<double>& matrix() { return A_; }
    const Eigen::SparseMatrix<double>& matrix() const { return A_; }
    // Changes whenever a pattern is built: a linear solver reuses its symbolic analysis while
    // the id stays the same.
    std::uint64_t pattern_id() const { return pattern_id_; }
    int n_equations() const { return static_cast<int>(A_.rows()); }
    int dofs_per_element() const { return ndof_; }

    void zero_values();
    // Element matrix, column-major ndof x ndof (Eigen default); rows/columns of prescribed
    // DOFs are skipped, those of tied DOFs go to the master's equation.
    void add_element_matrix(int element, const double* Ke);
    void add_diagonal(int equation, double v);
    // Adds v at (row, col) of the reduced matrix; the entry must be in the pattern (an
    // element's or a coupling's), else std::out_of_range. A binary search per call: for the
    // few entries of contact tangents, not for element matrices.
    void add_value(int row_equation, int col_equation, double v);
    // Equation of each element DOF (local node-major), -1 when prescribed.
    std::span<const int> element_equations(int element) const {
        return {elem_eq_.data() + static_cast<std::size_t>(element) * ndof_,
                static_cast<std::size_t>(ndof_)};
    }

    int n_colours() const { return static_cast<int>(colour_offsets_.size()) - 1; }
    std::span<const int> colour(int c) const {
        return {colour_elements_.data() + colour_offsets_[static_cast<std::size_t>(c)],
                static_cast<std::size_t>(colour_offsets_[static_cast<std::size_t>(c) + 1] -
                                         colour_offsets_[static_cast<std::size_t>(c)])};
    }

private:
    void build_pattern(int n_eq, int n_elements,
                       const std::vector<std::array<int, 2>>& extra_equations);
    void build_colours(const Mesh& mesh, int n_nodes);

    int ndof_ = 0;
    Eigen::SparseMatrix<double> A_;
    std::vector<int> elem_eq_;   // element * ndof + local
    std::vector<int> positions_; // (element * ndof + col) * ndof + row -> value index or -1
    std::vector<int> diagonal_;  // per equation: value index of the diagonal
    std::vector<int> colour_offsets_;
    std::vector<int> colour_elements_;
    std::uint64_t pattern_id_ = 0;
};

} // namespace ifsim::fem
