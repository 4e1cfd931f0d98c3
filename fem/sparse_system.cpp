#include "fem/sparse_system.hpp"

#include <algorithm>
#include <atomic>
#include <limits>
#include <stdexcept>

namespace ifsim::fem {
namespace {

std::atomic<std::uint64_t> next_pattern_id{1};

} // namespace

SparseSystem::SparseSystem(const Mesh& mesh, const DofMap& dofs,
                           std::span<const std::array<int, 2>> couplings) {
    const int D = mesh.dim();
    const int nen = mesh.nodes_per_element();
    const int ne = mesh.n_elements();
    ndof_ = nen * D;
    elem_eq_.resize(static_cast<std::size_t>(ne) * ndof_);
    for (int e = 0; e < ne; ++e) {
        for (int a = 0; a < nen; ++a) {
            for (int i = 0; i < D; ++i) {
                elem_eq_[static_cast<std::size_t>(e * ndof_ + a * D + i)] =
                    dofs.equation[static_cast<std::size_t>(mesh.node(e, a) * D + i)];
            }
        }
    }
    std::vector<std::array<int, 2>> extra;
    extra.reserve(couplings.size());
    for (const auto& c : couplings) {
        const int r = dofs.equation.at(static_cast<std::size_t>(c[0]));
        const int q = dofs.equation.at(static_cast<std::size_t>(c[1]));
        if (r >= 0 && q >= 0) {
            extra.push_back({r, q});
        }
    }
    build_pattern(dofs.n_equations, ne, extra);
    build_colours(mesh, mesh.n_nodes());
    pattern_id_ = next_pattern_id.fetch_add(1);
}

void SparseSystem::build_pattern(int n_eq, int ne,
                                 const std::vector<std::array<int, 2>>& extra_equations) {
    std::vector<std::vector<int>> rows_of_col(static_cast<std::size_t>(n_eq));
    for (int j = 0; j < n_eq; ++j) {
        rows_of_col[static_cast<std::size_t>(j)].push_back(j); // diagonal always present
    }
    for (int e = 0; e < ne; ++e) {
        const auto eq = element_equations(e);
        for (int c : eq) {
            if (c < 0) {
                continue;
            }
            auto& col = rows_of_col[static_cast<std::size_t>(c)];
            for (int r : eq) {
                if (r >= 0) {
                    col.push_back(r);
                }
            }
        }
    }
    for (const auto& rc : extra_equations) {
        rows_of_col[static_cast<std::size_t>(rc[1])].push_back(rc[0]);
    }
    std::size_t nnz = 0;
    for (auto& col : rows_of_col) {
        std::sort(col.begin(), col.end());
        col.erase(std::unique(col.begin(), col.end()), col.end());
        nnz += col.size();
    }
    if (nnz > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
        throw std::length_error("the global matrix has more than 2^31 entries");
    }
    A_.resize(n_eq, n_eq);
    A_.resizeNonZeros(static_cast<Eigen::Index>(nnz));
    int* outer = A_.outerIndexPtr();
    int* inner = A_.innerIndexPtr();
    outer[0] = 0;
    for (int j = 0; j < n_eq; ++j) {
        const auto& col = rows_of_col[static_cast<std::size_t>(j)];
        std::copy(col.begin(), col.end(), inner + outer[j]);
        outer[j + 1] = outer[j] + static_cast<int>(col.size());
    }
    rows_of_col.clear();
    rows_of_col.shrink_to_fit();
    zero_values();

    const auto find = [&](int row, int col) {
        const int* b = inner + outer[col];
        const int* e = inner + outer[col + 1];
        return static_cast<int>(std::lower_bound(b, e, row) - inner);
    };
    diagonal_.resize(static_cast<std::size_t>(n_eq));
    for (int j = 0; j < n_eq; ++j) {
        diagonal_[static_cast<std::size_t>(j)] = find(j, j);
    }
    positions_.resize(static_cast<std::size_t>(ne) * ndof_ * ndof_);
    for (int e = 0; e < ne; ++e) {
        const auto eq = element_equations(e);
        int* pos = positions_.data() + static_cast<std::size_t>(e) * ndof_ * ndof_;
        for (int c = 0; c < ndof_; ++c) {
            for (int r = 0; r < ndof_; ++r) {
                pos[c * ndof_ + r] = (eq[c] >= 0 && eq[r] >= 0) ? find(eq[r], eq[c]) : -1;
            }
        }
    }
}

void SparseSystem::build_colours(const Mesh& mesh, int n_nodes) {
    const int ne = mesh.n_elements();
    const int nen = mesh.nodes_per_element();
    // Resources an element writes: its nodes (the full-length force vector) and its
    // equations (the matrix and the reduced residual).
    std::vector<std::vector<int>> used(static_cast<std::size_t>(n_nodes + n_equations()));
    std::vector<int> colour_of(static_cast<std::size_t>(ne));
    std::vector<char> forbidden;
    std::vector<int> resources;
    int n_colours = 0;
    for (int e = 0; e < ne; ++e) {
        resources.clear();
        for (int a = 0; a < nen; ++a) {
            resources.push_back(mesh.node(e, a));
        }
        for (int q : element_equations(e)) {
            if (q >= 0) {
                resources.push_back(n_nodes + q);
            }
        }
        std::sort(resources.begin(), resources.end());
        resources.erase(std::unique(resources.begin(), resources.end()), resources.end());
        forbidden.assign(static_cast<std::size_t>(n_colours) + 1, 0);
        for (int r : resources) {
            for (int c : used[static_cast<std::size_t>(r)]) {
                forbidden[static_cast<std::size_t>(c)] = 1;
            }
        }
        int c = 0;
        while (forbidden[static_cast<std::size_t>(c)]) {
            ++c;
        }
        n_colours = std::max(n_colours, c + 1);
        colour_of[static_cast<std::size_t>(e)] = c;
        for (int r : resources) {
            used[static_cast<std::size_t>(r)].push_back(c);
        }
    }
    colour_offsets_.assign(static_cast<std::size_t>(n_colours) + 1, 0);
    for (int e = 0; e < ne; ++e) {
        ++colour_offsets_[static_cast<std::size_t>(colour_of[static_cast<std::size_t>(e)]) + 1];
    }
    for (int c = 0; c < n_colours; ++c) {
        colour_offsets_[static_cast<std::size_t>(c) + 1] +=
            colour_offsets_[static_cast<std::size_t>(c)];
    }
    colour_elements_.resize(static_cast<std::size_t>(ne));
    std::vector<int> fill(colour_offsets_.begin(), colour_offsets_.end() - 1);
    for (int e = 0; e < ne; ++e) { // ascending element order inside each colour
        colour_elements_[static_cast<std::size_t>(
            fill[static_cast<std::size_t>(colour_of[static_cast<std::size_t>(e)])]++)] = e;
    }
}

void SparseSystem::zero_values() {
    std::fill(A_.valuePtr(), A_.valuePtr() + A_.nonZeros(), 0.0);
}

void SparseSystem::add_element_matrix(int element, const double* Ke) {
    const int* pos = positions_.data() + static_cast<std::size_t>(element) * ndof_ * ndof_;
    double* values = A_.valuePtr();
    const int n = ndof_ * ndof_;
    for (int k = 0; k < n; ++k) {
        if (pos[k] >= 0) {
            values[pos[k]] += Ke[k];
        }
    }
}

void SparseSystem::add_value(int row_equation, int col_equation, double v) {
    const int* inner = A_.innerIndexPtr();
    const int* outer = A_.outerIndexPtr();
    const int* b = inner + outer[col_equation];
    const int* e = inner + outer[col_equation + 1];
    const int* it = std::lower_bound(b, e, row_equation);
    if (it == e || *it != row_equation) {
        throw std::out_of_range("SparseSystem::add_value: entry not in the sparse pattern");
    }
    A_.valuePtr()[it - inner] += v;
}

void SparseSystem::add_diagonal(int equation, double v) {
    A_.valuePtr()[diagonal_[static_cast<std::size_t>(equation)]] += v;
}

} // namespace ifsim::fem
