#include "io/boundary_value/tangent_check_file.hpp"

#include <fstream>
#include <stdexcept>

#include <fmt/format.h>

namespace ifsim::io {

void write_tangent_checks(const std::filesystem::path& dir, const fem::StaticSolver& solver) {
    const std::filesystem::path path = dir / "tangent-check.csv";
    std::ofstream out(path);
    if (!out) {
        throw std::runtime_error(fmt::format("{}: cannot be written", path.string()));
    }
    const fem::Mesh& mesh = solver.mesh();
    const int dim = mesh.dim();
    out << "stage,t_end,iteration,step,mismatch,worst_node,worst_direction,x,y,z,"
           "worst_difference,worst_tangent";
    for (const auto& pair : solver.contacts()) {
        out << ",pair." << pair->spec().name;
    }
    out << ",rest,rest_worst_node,rest_worst_direction\n";
    for (const fem::TangentCheckRecord& r : solver.tangent_checks()) {
        const int node = r.worst_dof >= 0 ? r.worst_dof / dim : -1;
        double x[3] = {0.0, 0.0, 0.0};
        for (int d = 0; d < dim && node >= 0; ++d) {
            x[d] = mesh.coordinates[static_cast<std::size_t>(node * dim + d)];
        }
        out << fmt::format("{},{:.17g},{},{:.3g},{:.6e},{},{},{:.6g},{:.6g},{:.6g},{:.6e},{:.6e}",
                           r.stage, r.t_end, r.iteration, r.step, r.mismatch, node,
                           node >= 0 ? r.worst_dof % dim : -1, x[0], x[1], x[2], r.worst_difference,
                           r.worst_tangent);
        for (const double m : r.pairs) {
            out << fmt::format(",{:.6e}", m);
        }
        out << fmt::format(",{:.6e},{},{}\n", r.rest,
                           r.rest_worst_dof >= 0 ? r.rest_worst_dof / dim : -1,
                           r.rest_worst_dof >= 0 ? r.rest_worst_dof % dim : -1);
    }
    if (!out) {
        throw std::runtime_error(fmt::format("{}: write failed", path.string()));
    }
}

} // namespace ifsim::io
