#pragma once
// history.csv of a boundary-value run: one row per converged increment and row 0 for the
// initial state. Columns:
//   increment,stage,time,newton_iterations,u_t1,u_t2,u_n,t_n,t_t1,t_t2,
//   cuts,residual,closed_points,s_p1,s_p2,eps_n,band_thickness,e_interface
// u_t1, u_t2: mean x, y (3D) displacement of [output] plate minus that of soil_top; u_n:
// vertical displacement of soil_top minus that of plate (dilation positive); t_n: mean normal
// traction on the soil (negative in compression); t_t1, t_t2: mean shear traction on the soil
// along global x, y (3D), positive when the plate moving +x drags the soil. With [interface]
// the tractions are the contact's area-weighted means; without it they come from the
// reactions (internal - external force) on the nodes of traction_faces over the set's area.
// Row 0 takes them from the soil's initial stress on the faces (sigma n).
// closed_points: contact points in compression (empty without [interface]); s_p1, s_p2,
// eps_n, band_thickness, e_interface: the continuum interface's means (empty for Coulomb
// friction and without [interface]).
// With contact the main contact columns (t_n, t_t1, t_t2, closed_points, s_p1, ...) describe
// the pair named by [output] contact (default: the first pair). With more than one pair the
// row ends with <name>.t_n,<name>.t_t1,<name>.t_t2,<name>.closed_points for every pair in the
// scene's order, each the pair's own means as above.

#include <optional>
#include <string>
#include <vector>

#include "fem/static_solver.hpp"
#include "io/boundary_value/boundary_value_scene.hpp"
#include "io/mesh/face_geometry.hpp"
#include "io/output/history_writer.hpp"

namespace ifsim::io {

// One pair's means: <name>.t_n, <name>.t_t1, <name>.t_t2, <name>.closed_points.
struct PairTractions {
    double t_n = 0.0, t_t1 = 0.0, t_t2 = 0.0;
    int closed_points = 0;
};

struct BoundaryValueRow {
    long increment = 0;
    int stage = 0;
    double time = 0.0; // completed stages + pseudo-time in the stage
    int newton_iterations = 0;
    double u_t1 = 0.0, u_t2 = 0.0, u_n = 0.0;
    double t_n = 0.0, t_t1 = 0.0, t_t2 = 0.0;
    int cuts = 0;          // halvings of the step for this increment
    double residual = 0.0; // last relative residual
    std::optional<int> closed_points;
    std::optional<double> s_p1, s_p2, eps_n, band_thickness, e_interface;
    std::vector<PairTractions> pairs; // every pair's, only with more than one pair
};

std::vector<std::string> boundary_value_history_columns(const BoundaryValueScene& scene);
void write_boundary_value_row(HistoryWriter& out, const BoundaryValueRow& row);

// The measurements of a row from the solver's committed state.
class BoundaryValueProbe {
public:
    explicit BoundaryValueProbe(const BoundaryValueScene& scene);

    // Displacements and tractions of the converged state.
    void measure(const fem::StaticSolver& solver, BoundaryValueRow& row) const;
    // Row 0: zero displacements, tractions sigma n from the initial stress on the faces.
    void initial(const fem::StaticSolver& solver, BoundaryValueRow& row) const;

private:
    double mean(const fem::StaticSolver& solver, const std::vector<int>& nodes, int d) const;
    // sigma n of the initial stress over a face set, area-weighted; also the mean stress.
    PairTractions initial_tractions(const fem::StaticSolver& solver, const std::string& faces,
                                    const FaceGeometry& geometry, fem::Voigt6& mean_stress) const;

    const BoundaryValueScene& scene_;
    const BoundaryValueInterface* main_; // the main columns' pair, nullptr without contact
    int dim_;
    std::string faces_; // the main pair's slave faces or traction_faces
    FaceGeometry geometry_;
    std::vector<int> plate_, soil_top_, face_nodes_;
    std::vector<FaceGeometry> pair_geometry_; // each pair's slave faces, with several pairs
};

} // namespace ifsim::io
