#pragma once
// What a stage applies besides its constraints: springs to ground (each continuing from the
// previous stage that named it), gravity and face pressures ramped over pseudo-time. The unit
// load vectors are built when a stage first asks for them and reused by every later stage.

#include <map>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "fem/mesh.hpp"
#include "fem/stage.hpp"

namespace ifsim::fem {

struct LoadCounters {
    long gravity_load_builds = 0;       // unit gravity vectors integrated
    long gravity_load_applications = 0; // evaluations with gravity in the external force
    long pressure_load_builds = 0;
};

struct LoadTimers {
    double gravity = 0.0;  // building and scaling the gravity load
    double pressure = 0.0; // building and scaling face pressures
};

class StageLoads {
public:
    // Throws std::invalid_argument for a spring direction the mesh does not have, std::out_of
    // range for an unknown node or face set; nothing changes then.
    static void check(const Mesh& mesh, const Stage& stage);

    // The stage's springs, with the displacement u at the stage's start as the reference of
    // those that are new; its unit loads (gravity with the elements' densities).
    void begin(const Mesh& mesh, const Stage& stage, std::span<const double> u,
               const std::vector<double>& densities);
    // f = f_ext at pseudo-time t of the stage (overwritten, full length).
    void external_force(double t, std::vector<double>& f);
    // Spring forces of the displacement u + du added to f_int; their stiffness on the
    // diagonal of the equations (eq < 0: prescribed, skipped).
    void add_spring_forces(std::span<const double> u, std::span<const double> du,
                           std::vector<double>& f_int) const;
    template <typename AddDiagonal>
    void add_spring_stiffness(const std::vector<int>& equation, AddDiagonal add) const {
        for (const Spring& sp : springs_) {
            for (int d : sp.dofs) {
                const int eq = equation[static_cast<std::size_t>(d)];
                if (eq >= 0) {
                    add(eq, sp.stiffness);
                }
            }
        }
    }

    const LoadCounters& counters() const { return counters_; }
    const LoadTimers& timers() const { return timers_; }

    // The springs' reference displacements (a spring continues from the stage before: state
    // a snapshot carries), in the running stage's spring order.
    std::vector<std::vector<double>> spring_references() const {
        std::vector<std::vector<double>> out;
        for (const Spring& sp : springs_) {
            out.push_back(sp.reference);
        }
        return out;
    }
    // Throws std::invalid_argument when the snapshot's springs are not the running stage's.
    void set_spring_references(const std::vector<std::vector<double>>& references);

private:
    struct Spring {
        std::string key;
        std::vector<int> dofs;
        std::vector<double> reference;
        double stiffness = 0.0; // per node
    };

    Stage stage_;
    std::vector<Spring> springs_;
    std::vector<double> gravity_unit_; // empty until a stage asks for gravity
    std::map<std::string, std::vector<double>> pressure_unit_;
    LoadCounters counters_;
    LoadTimers timers_;
};

} // namespace ifsim::fem
