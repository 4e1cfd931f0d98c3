#pragma once
// Recorders of a boundary-value run ([[recorder]] entries; docs/scenes.md "Recorders"): extra
// history.csv columns that are not tied to a shear box.
//
//   [[recorder]]                  the mean displacement of a node set along a direction
//   name = "wall"                 -> column "wall" (m)
//   nodes = "wall2.all"
//   direction = [0.0, 0.0, -1.0]  (normalised)
//
//   [[recorder]]                  the state of the contact point nearest to a position
//   name = "p"                    (reference configuration) -> columns "p.t_n", "p.t_t1",
//   contact = "rough"             "p.t_t2" (the pair's frame), "p.s_p1", "p.s_p2", "p.eps_n",
//   position = [1.2, 0.125, 0.8]  "p.eps_p1", "p.eps_p2", "p.band_thickness", "p.e_interface"
//
// A point recorder takes the nearest slave point of its pair at the pair's first pairing (the
// first increment); row 0 and, for a Coulomb pair, the band columns are empty.

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "fem/static_solver.hpp"
#include "io/boundary_value/boundary_value_contacts.hpp"
#include "io/boundary_value/pair_frame.hpp"
#include "io/output/column_units.hpp"
#include "io/scene/table_reader.hpp"

namespace ifsim::io {

struct NodeRecorder {
    std::string name;
    std::string nodes;
    Vec3 direction{}; // unit
};

struct PointRecorder {
    std::string name;
    std::size_t contact = 0; // pair index
    Vec3 position{};
};

struct Recorders {
    std::vector<NodeRecorder> nodes;
    std::vector<PointRecorder> points;
    bool empty() const { return nodes.empty() && points.empty(); }
};

// The [[recorder]] entries. Throws SceneError naming the file and key.
Recorders read_recorders(const TableReader& root, const fem::Mesh& mesh,
                         const std::vector<BoundaryValueInterface>& contacts);

// The recorders' columns in history.csv order, and their units.
std::vector<std::string> recorder_columns(const Recorders& r);
std::vector<std::pair<std::string, ColumnDescription>> recorder_descriptions(const Recorders& r);

// Measures the recorders in the solver's committed state; resolves each point recorder's
// point once its pair is paired.
class RecorderProbe {
public:
    RecorderProbe(const Recorders& r, const fem::Mesh& mesh,
                  const std::vector<BoundaryValueInterface>& contacts);
    // One value per column (empty where there is none: row 0, a Coulomb pair's band).
    std::vector<std::optional<double>> measure(const fem::StaticSolver& solver);
    std::vector<std::optional<double>> initial() const;
    // The chosen points, for summary.json: name, requested and actual position.
    nlohmann::ordered_json chosen_points() const;

private:
    const Recorders& recorders_;
    const fem::Mesh& mesh_;
    std::vector<std::vector<int>> node_sets_;
    std::vector<PairFrame> frames_; // per point recorder
    std::vector<long> chosen_;      // point index per point recorder, -1 before pairing
    std::vector<Vec3> chosen_at_;   // its reference position
};

} // namespace ifsim::io
