#pragma once
// One contact pair as the static solver drives it: mortar kinematics (2D or 3D) feeding a
// batched contact engine — Coulomb penalty friction or a continuum model used as interface
// model through Algorithm 1 (novel or Stutz formulation) — and the engine's tractions and
// Jacobian columns turned back into nodal forces and tangent entries (paper Appendix A).
//
// Per increment (attempt): begin_increment() pairs the slave points with the master in the
// converged configuration and gathers the frame and the continuum stress extrapolated from the
// slave elements' integration points and rotated into the frame (Eqs. 14-16). Per Newton
// iteration: evaluate() (gaps for the trial increment, the engine update with its Jacobian
// columns, forces into f_int) and, when the solver needs the tangent, add_tangent() from the
// same evaluation. commit() after convergence.
//
// Normal contact is a penalty: t_N = k_N (g_N - g_0) while that is <= 0. With `prestressed`
// (default) g_0 is set at the first pairing so that t_N equals the continuum's normal stress
// there: the contact starts in equilibrium with an initial (K0) stress state, as an initial
// stress state of the soil demands. The local t1 follows `shear_direction` projected onto the
// contact plane (default the global x axis), so "shear along +t1" means the same in every
// scene regardless of how the master faces happen to be ordered.

#include <array>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "engine/contact_update.hpp"
#include "engine/failed_contact_point.hpp"
#include "engine/model_registry.hpp"
#include "fem/mesh.hpp"
#include "fem/mortar_kinematics.hpp"
#include "fem/stress_extrapolation.hpp"
#include "kernels/coulomb.hpp"

namespace ifsim::fem {

// The model state of an interface point from the continuum stress at the point in its local
// frame (Voigt: 11 = normal, 22 = t1, 33 = t2, 12 = n-t1, 13 = n-t2, 23 = t1-t2). The caller
// decides what the interface takes from it (novel: sigma_N, sigma_p1, sigma_p2 and the shear;
// Stutz from the normal contact: all three normal components equal to sigma_N).
using InterfaceStateFromStress = std::function<std::vector<double>(const Voigt6& local_stress)>;

struct ContactPairSpec {
    std::string name = "interface";
    std::string slave_faces;       // the soil side: its continuum stress feeds Eq. 14
    std::string master_faces;      // the structure
    double normal_penalty = 1.0e8; // k_N, kPa/m
    bool prestressed = true;
    std::array<double, 3> shear_direction{1.0, 0.0, 0.0};
    CoulombParams friction;                 // coulomb (options.interface.formulation)
    MaterialChoice interface_material;      // continuum (hypoplasticity or sanisand)
    InterfaceStateFromStress initial_state; // continuum
    ContactOptions options;                 // formulation; continuum: Algorithm 1, Jacobian
    // Continuum, Eq. 37 / Eqs. 39-40: a residual evaluation runs the base lanes only and the
    // Jacobian lanes run (with the base lanes again) when the tangent is asked for. Same
    // results, 25 % fewer lanes in the shear-box scenes, but not faster: the base lanes are the
    // costly ones (bench_fe_shear_box: 2D 9-16 % slower, 3D 5-11 % faster), so off by default.
    bool defer_jacobian = false;
    // Continuum with adaptive sub-increments: true holds each point's sub-increments, chosen by
    // the error control in the increment's first evaluation, as that many equal ones through
    // the Newton iterations that follow (chosen again after convergence where the slip moved
    // by more than (partition_regrowth - 1) times the one they were chosen for); false chooses
    // them anew in every
    // evaluation. Held, the residual is one smooth function of the displacement within an
    // increment and the base lane takes one Algorithm 1 solve per sub-increment instead of
    // the step doubling's three (docs/fem.md, "Sub-increments held through an increment").
    bool hold_partition = true;
    double partition_regrowth = 1.5;
    // Continuum: a viscous shear traction eta dg_T / dt on top of the band's (kPa per m of slip
    // per nominal step, dt the increment's share of its nominal step; 0: off). A
    // regularisation for a band past its peak under load control, where no equilibrium near
    // the last one exists (docs/fem.md, "Slip viscosity"); not part of the paper's equations.
    // In every increment, or (`slip_viscosity_always` false) only in increments that failed at
    // the finest cut: the solver retries them with it (StaticSolver::stage_from).
    double slip_viscosity = 0.0;
    bool slip_viscosity_always = true;

    bool coulomb() const { return options.interface.formulation == InterfaceFormulation::coulomb; }
};

struct ContactPairTimers {
    double search = 0.0;  // pairing: projection of the slave points onto the master
    double gather = 0.0;  // frames, extrapolated stresses, gaps into the engine's arrays
    double kernels = 0.0; // the contact engine's batched update (with Jacobian lanes)
    double scatter = 0.0; // tractions to nodal forces and tangent entries
};

struct ContactPairCounters {
    long evaluations = 0;       // engine updates (one per residual evaluation)
    double point_updates = 0.0; // contact-point updates (base lanes)
    double lanes = 0.0;         // Algorithm 1 runs incl. Jacobian lanes
    double subincrements = 0.0; // Algorithm 1 sub-increments of the base lanes
    double constitutive_evaluations = 0.0;
    double model_substeps = 0.0; // substeps of the interface model's own integration
    double interface_newton_iterations = 0.0;
    long failed_evaluations = 0;
    long band_clamped = 0;
    double dropped_columns = 0.0;
    double newton_fallbacks = 0.0; // Algorithm 1 calls that took their second try
    // Novel formulation: engine re-runs after a point failed with the continuum's in-plane
    // stresses as targets, and committed point updates whose targets were relaxed (Eqs. 19-20
    // held only in part: an admissible jump of sigma_p, Eq. 13).
    long relaxed_reruns = 0;
    double relaxed_point_updates = 0.0;
    // Slip viscosity: committed point updates whose viscous traction exceeded 1 % of the
    // band's shear traction (or of 1 % of |t_N| where that is larger), the largest such share
    // and the largest viscous traction (kPa).
    double viscous_point_updates = 0.0;
    double viscous_share_max = 0.0;
    double viscous_traction_max = 0.0;
};

// Area-weighted means over the points in contact (committed state after commit()).
struct ContactResultant {
    double area = 0.0; // of the active points (per m of thickness in 2D)
    int active = 0;
    int closed = 0;
    double t_N = 0.0;                      // mean normal traction, negative in compression
    std::array<double, 3> shear{};         // mean shear traction on the slave body, global axes
    double void_ratio = 0.0;               // interface zone (continuum formulations)
    double eps_N = 0.0;                    // interface normal strain
    double band_thickness = 0.0;           // d_s (Eq. 26)
    double sigma_p1 = 0.0, sigma_p2 = 0.0; // interface in-plane stresses
};

// One contact point after the last converged increment, for field output. What a pair does
// not have (a Coulomb pair's band) is NaN.
struct ContactPointRecord {
    int slave_element = -1;          // the slave face's element
    std::array<double, 3> natural{}; // natural coordinates of the point in that element
    bool active = false;             // projects inside the master surface
    double weight = 0.0;             // Gauss weight times surface Jacobian (area share)
    double t_N = 0.0;                // normal traction, negative in compression
    std::array<double, 3> shear{};   // shear traction on the slave body, global axes
    double open = 0.0;               // 1: open (t_N above the opening threshold or >= 0)
    double slipping = std::numeric_limits<double>::quiet_NaN(); // Coulomb: 1 while sliding
    double sigma_p1 = std::numeric_limits<double>::quiet_NaN(); // interface in-plane stresses
    double sigma_p2 = std::numeric_limits<double>::quiet_NaN();
    double eps_N = std::numeric_limits<double>::quiet_NaN(); // interface strains (Eqs. 18-20)
    double eps_p1 = std::numeric_limits<double>::quiet_NaN();
    double eps_p2 = std::numeric_limits<double>::quiet_NaN();
    double band_thickness = std::numeric_limits<double>::quiet_NaN(); // d_s (Eq. 26)
    double void_ratio = std::numeric_limits<double>::quiet_NaN();     // of the interface zone
    double subincrements = std::numeric_limits<double>::quiet_NaN();  // Algorithm 1, last call
};

// A pair's committed state between increments (SolverSnapshot): its points' committed state
// columns (column after column), the prestress offsets of the penalty, and the novel
// interface's relaxation of its targets.
struct ContactPairSnapshot {
    bool started = false; // the first pairing set the offsets and the points' initial state
    std::vector<double> committed;
    std::vector<double> gap_offset;
    std::vector<double> relax;
    std::vector<double> calm;
};

// Continuum stress (Voigt) at the integration points of an element, solver order.
using ElementStresses = std::function<void(int element, std::vector<Voigt6>& stresses)>;

class ContactPair {
public:
    virtual ~ContactPair() = default;
    virtual const ContactPairSpec& spec() const = 0;
    virtual const MortarKinematics& kinematics() const = 0;

    // Pairing and gather at the start of an increment; true when the DOF couplings changed.
    virtual bool begin_increment(const Mesh& mesh, const std::vector<double>& u,
                                 const ElementStresses& stresses) = 0;
    // Tractions for the trial increment du, forces added to f_int. False (with a message
    // naming the failed point) when the contact engine failed: the caller cuts the increment.
    virtual bool evaluate(const std::vector<double>& du, std::vector<double>& f_int,
                          std::string& error) = 0;
    // Tangent entries of the last evaluate().
    virtual void add_tangent(std::vector<ContactTriplet>& K) = 0;
    virtual void commit() = 0;
    // Implicit gather (novel formulation): the continuum stress extrapolated again from the
    // given (trial) stresses replaces the in-plane targets of the next evaluate(); returns the
    // largest change of a target relative to max(|s_p|, 1 kPa). 0 for pairs without targets.
    virtual double regather(const ElementStresses&) { return 0.0; }
    // Back to the targets before the last regather (it was a probe).
    virtual void restore_targets() {}
    // The last regather did not settle: its targets become the Aitken-relaxed step from the
    // targets before it (SolverSettings::gather_aitken; the history restarts each increment).
    virtual void relax_targets() {}
    // After Newton converged with sub-increments held through the increment
    // (ContactPairSpec::hold_partition): the points whose slip moved by more than
    // (partition_regrowth - 1) times the one their sub-increments were chosen for (at least the
    // paper's sub-increment of slip) choose again in the next evaluation.
    // Returns how many will (0: the held sub-increments stand).
    virtual std::size_t release_outgrown_partitions() { return 0; }
    // The last evaluation is an iterate the Newton iteration goes on from: points that chose
    // their sub-increments in it hold that count for the rest of the increment.
    virtual void hold_chosen_partitions() {}
    // The increment about to be solved as a share of its nominal step (1 uncut): the slip
    // viscosity's time.
    virtual void set_increment_length(double /*dt*/) {}
    // Slip viscosity of the pairs that keep it for failed increments: on for a retry.
    virtual void set_viscous_retry(bool /*on*/) {}
    // The pair has a slip viscosity kept for failed increments.
    bool viscous_fallback() const {
        return spec().slip_viscosity > 0.0 && !spec().slip_viscosity_always && !spec().coulomb();
    }

    virtual ContactResultant resultant() const = 0;
    // Every point of the pair in the state of the last converged increment.
    virtual std::vector<ContactPointRecord> point_records() const = 0;
    // The point whose Algorithm 1 call made the last evaluate() fail (continuum interfaces;
    // empty when that evaluation succeeded): its replay (io/replay/interface_replay.hpp).
    virtual std::optional<FailedContactPoint> last_failure() const { return std::nullopt; }
    virtual void forget_failure() {}
    // The base-lane Algorithm 1 call with the most interface-model substeps so far (continuum
    // interfaces; failed or not), for its replay: where one hard increment's time went.
    // `cause` is its failure code (0: it succeeded).
    virtual std::optional<FailedContactPoint> costliest_call() const { return std::nullopt; }
    // The committed state, and back (throws std::invalid_argument for another pair's).
    virtual ContactPairSnapshot snapshot() const = 0;
    virtual void restore(const ContactPairSnapshot& snapshot) = 0;
    const ContactPairTimers& timers() const { return timers_; }
    const ContactPairCounters& counters() const { return counters_; }
    std::vector<std::array<int, 2>> couplings() const { return kinematics().couplings(); }

    // While probing (the solver's first guesses), an evaluation that fails leaves no lasting
    // trace: no relaxed targets, no failure counted.
    void set_probing(bool on) { probing_ = on; }

protected:
    bool probing_ = false;
    ContactPairTimers timers_;
    ContactPairCounters counters_;
};

// The mortar kinematics of the mesh's dimension for the spec's face sets, and the pair.
// Throws std::invalid_argument for unknown face sets, a continuum pair without a state
// function, or a Coulomb pair with negative parameters.
std::unique_ptr<ContactPair> make_contact_pair(const Mesh& mesh, ContactPairSpec spec);

} // namespace ifsim::fem
