#pragma once
// history.csv of a boundary-value run: one row per converged increment and row 0 for the
// initial state. Columns (docs/scenes.md "Outputs"):
//   increment,stage,time,newton_iterations,u_t1,u_t2,u_n,t_n,t_t1,t_t2,
//   cuts,residual,closed_points,s_p1,s_p2,eps_n,band_thickness,e_interface
// With contact, the main columns describe the pair named by [output] contact (default: the
// first) in its own frame (io/boundary_value/pair_frame.hpp: n the slave faces' outward normal,
// t1 along the pair's shear_direction, t2 = t1 x n): t_n, t_t1, t_t2 its mean tractions on the
// soil; u_t1, u_t2 the mean displacement of [output] plate minus that of soil_top along t1,
// t2; u_n that difference along n (soil_top minus plate along -n: dilation positive). A shear
// box with the default shear direction +x reads as always (t1 = x, t2 = y, n = -vertical).
// Without contact: u_t1, u_t2 along x, y, u_n vertical, and the tractions from the reactions
// on traction_faces. Row 0 takes the tractions from the soil's initial stress on the faces.
// closed_points, s_p1, ..., e_interface: the continuum interface's means (empty for Coulomb
// friction and without contact).
// With more than one pair every row ends with <name>.t_n,<name>.t_t1,<name>.t_t2,
// <name>.closed_points per pair in the scene's order, then (appended later)
// <name>.u_n,<name>.u_t1,<name>.u_t2,<name>.F_n,<name>.F_t1,<name>.F_t2 per pair, all in the
// pair's frame: mean tractions, the mean displacement of its master faces' nodes minus
// its slave faces' nodes (u_n along n: opening positive), and the resultant forces on the
// soil (kN; per m in 2D). Then the [[recorder]] columns (boundary_value_recorders.hpp).

#include <optional>
#include <string>
#include <vector>

#include "fem/static_solver.hpp"
#include "io/boundary_value/boundary_value_recorders.hpp"
#include "io/boundary_value/boundary_value_scene.hpp"
#include "io/boundary_value/pair_frame.hpp"
#include "io/mesh/face_geometry.hpp"
#include "io/output/history_writer.hpp"

namespace ifsim::io {

// One pair's measures in its frame: <name>.t_n, .t_t1, .t_t2, .closed_points, .u_n, .u_t1,
// .u_t2, .F_n, .F_t1, .F_t2.
struct PairTractions {
    double t_n = 0.0, t_t1 = 0.0, t_t2 = 0.0;
    int closed_points = 0;
    double u_n = 0.0, u_t1 = 0.0, u_t2 = 0.0;
    double F_n = 0.0, F_t1 = 0.0, F_t2 = 0.0;
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
    std::vector<PairTractions> pairs;             // every pair's, only with more than one pair
    std::vector<std::optional<double>> recorders; // [[recorder]] columns
};

std::vector<std::string> boundary_value_history_columns(const BoundaryValueScene& scene);
void write_boundary_value_row(HistoryWriter& out, const BoundaryValueRow& row);

// The measurements of a row from the solver's committed state.
class BoundaryValueProbe {
public:
    explicit BoundaryValueProbe(const BoundaryValueScene& scene);

    // Displacements and tractions of the converged state (resolves the point recorders'
    // points at the first measurement after the pairs are paired).
    void measure(const fem::StaticSolver& solver, BoundaryValueRow& row);
    // Row 0: zero displacements, tractions sigma n from the initial stress on the faces.
    void initial(const fem::StaticSolver& solver, BoundaryValueRow& row) const;
    const RecorderProbe& recorders() const { return recorders_; }

private:
    // The mean of displacement component d over nodes, and the mean vector.
    Vec3 mean(const fem::StaticSolver& solver, const std::vector<int>& nodes) const;
    // sigma n of the initial stress over a face set, area-weighted, in the frame; also the
    // mean stress.
    PairTractions initial_tractions(const fem::StaticSolver& solver, const std::string& faces,
                                    const FaceGeometry& geometry, const PairFrame& frame,
                                    fem::Voigt6& mean_stress) const;

    const BoundaryValueScene& scene_;
    const BoundaryValueInterface* main_; // the main columns' pair, nullptr without contact
    int dim_;
    std::string faces_; // the main pair's slave faces or traction_faces
    FaceGeometry geometry_;
    PairFrame frame_; // the main pair's; without contact x, y and the faces' normal
    std::vector<int> plate_, soil_top_, face_nodes_;
    // Each pair's slave face geometry, frame and face nodes, with several pairs.
    std::vector<FaceGeometry> pair_geometry_;
    std::vector<PairFrame> pair_frames_;
    std::vector<std::vector<int>> pair_slave_nodes_, pair_master_nodes_;
    RecorderProbe recorders_;
};

} // namespace ifsim::io
