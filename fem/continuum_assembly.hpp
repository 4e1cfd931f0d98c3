#pragma once
// The continuum of a finite-element model: its element sets with their material points (one
// batched SetMaterial per set), the integration-point geometry, and the element loops that
// turn a displacement increment into strain increments, stresses into internal forces and
// material tangents into the global matrix.
//
// Kinematics (SolverSettings::kinematics): small strain builds the geometry once from the
// reference configuration, strains are B du, forces B^T sigma dV and tangents B^T D B dV
// (fem/element_kernels.hpp). Updated Lagrangian (fem/finite_strain.hpp) rebuilds the geometry
// on the configuration of each increment's start (begin_increment), takes the strain increment
// and spin of the midpoint configuration, turns the material points' start state with the
// Hughes-Winget rotation (Zaremba-Jaumann rate), and forms forces and tangents from the first
// Piola-Kirchhoff stress of the increment. Hourglass control acts on the total displacement
// with the reference configuration's base vectors in both (a rigid rotation, linear in X, has
// no hourglass part). A small-strain run calls none of the finite-strain code.

#include <algorithm>
#include <array>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "fem/element_geometry.hpp"
#include "fem/mesh.hpp"
#include "fem/set_material.hpp"
#include "fem/solver_settings.hpp"
#include "fem/sparse_system.hpp"
#include "fem/stress_extrapolation.hpp"

namespace ifsim::fem {

struct ContinuumCounters {
    long constitutive_evaluations = 0; // point updates incl. perturbation lanes
    long tangent_evaluations = 0;      // of which perturbation lanes
    long tangent_fallbacks = 0;        // points whose perturbation lanes failed (rate used)
    long failed_point_updates = 0;     // base updates with status failed
    long k0_points = 0;                // integration points given a K0 initial stress
    long unreliable_committed = 0;     // committed point updates on which a safeguard acted
    long geometry_updates = 0;         // updated Lagrangian: geometries of a new configuration
};

// The prescribed DOFs' part of a tangent (the tangent predictor): while assembling, every
// entry K(r, c) with r free and c prescribed adds -K(r, c) du_p(c) to rhs(r).
struct PrescribedCoupling {
    std::span<const double> prescribed_du; // full DOF vector, zero at free DOFs
    std::vector<double>& rhs;              // reduced (per equation)
};

class ContinuumAssembly {
public:
    // Throws std::invalid_argument for an element without material or in two sets, an
    // initial state of the wrong length, or an inverted element. Applies the sets' K0 stress.
    ContinuumAssembly(const Mesh& mesh, std::vector<ElementSetMaterial> materials,
                      const SolverSettings& settings, double& k0_seconds);
    ~ContinuumAssembly();

    // Updated Lagrangian: the geometry of the configuration X + u of the increment's start
    // (rebuilt when u changed). Throws std::invalid_argument naming an inverted element.
    // Nothing to do with small strain.
    void begin_increment(const Mesh& mesh, std::span<const double> u);
    // Strain increments of every integration point from the displacement increment.
    void strains(const Mesh& mesh, std::span<const double> du);
    // Trial states from the strain increments; false (error names set, element and point)
    // when a point failed.
    bool update(std::string& error);
    // Material tangents at the trial states (after update()).
    void material_tangents(int dim);
    // f_int of the trial stresses (plus hourglass forces of the total displacement u + du);
    // f is overwritten, full DOF length.
    void internal_force(const Mesh& mesh, const SparseSystem& system, std::span<const double> u,
                        std::span<const double> du, std::vector<double>& f);
    // Element tangents scattered into the (zeroed) system matrix, colour by colour; with a
    // coupling, the prescribed DOFs' columns go to its right-hand side.
    void tangent(const Mesh& mesh, SparseSystem& system, PrescribedCoupling* coupling);
    void commit();

    std::vector<double> state(int element, int point) const; // committed
    // Every set's committed states, set after set, point after point (snapshots), and back.
    std::vector<double> committed_states() const;
    void restore_committed_states(const std::vector<double>& states);
    std::vector<double> trial_state(int element, int point) const; // last evaluation
    void element_stresses(int element, std::vector<Voigt6>& out, bool trial) const;
    // Density of every element (t/m^3), for the gravity load.
    std::vector<double> densities(int n_elements) const;
    const ElementGeometry& geometry() const { return geom_; }
    const ContinuumCounters& counters() const { return counters_; }

private:
    struct SetData;
    // Elements per task in a colour's loop: a small mesh's colours hold a few dozen elements,
    // fewer than element_grain, and ran as one task each (the coarse §6 twin's assembly took
    // 3.5 s on one thread and 3.1 s on two). Split a colour into up to 8 tasks of at least 8
    // elements; the split depends on the colour's size only.
    std::size_t colour_grain(std::size_t n) const {
        return std::min(std::max<std::size_t>(settings_.element_grain, 1),
                        std::max<std::size_t>(8, (n + 7) / 8));
    }
    template <int D>
    void strains_d(const Mesh& mesh, std::span<const double> du);
    template <int D, class PointForces>
    void force_loop(const Mesh& mesh, const SparseSystem& system, std::span<const double> u,
                    std::span<const double> du, std::vector<double>& f,
                    const ElementGeometry& hourglass, PointForces&& point_forces);
    template <int D>
    void strains_ul(const Mesh& mesh, std::span<const double> du);
    template <int D>
    bool inverted_at_gauss_points(const Mesh& mesh, int e, const double* ue) const;
    template <int D>
    void internal_force_ul(const Mesh& mesh, const SparseSystem& system, std::span<const double> u,
                           std::span<const double> du, std::vector<double>& f);
    template <int D>
    void tangent_ul(const Mesh& mesh, SparseSystem& system, PrescribedCoupling* coupling);
    template <int D>
    void scatter_tangent(const Mesh& mesh, SparseSystem& system, PrescribedCoupling* coupling,
                         int e, const double* K);
    template <int D>
    void internal_force_d(const Mesh& mesh, const SparseSystem& system, std::span<const double> u,
                          std::span<const double> du, std::vector<double>& f);
    template <int D>
    void tangent_d(const Mesh& mesh, SparseSystem& system, PrescribedCoupling* coupling);
    void apply_k0(int dim, double& k0_seconds);
    void hourglass_stiffness(int n_elements);
    const SetData& set_of(int element) const;
    std::size_t point_of(int element, int q) const;

    SolverSettings settings_;
    ElementGeometry geom_; // small strain: the reference; updated Lagrangian: of the increment
    // Updated Lagrangian: the reference geometry (hourglass base vectors), the displacement
    // geom_ was built for, each point's increment gradient G (9 per point, row-major) and
    // the elements whose increment inverts them (the update fails).
    ElementGeometry reference_;
    std::vector<double> configured_u_;
    std::vector<double> increment_gradients_;
    std::vector<int> inverted_;
    std::vector<unsigned char> inverted_flags_; // per element, reused
    std::vector<std::unique_ptr<SetData>> sets_;
    std::vector<int> set_of_element_;
    std::vector<int> local_of_element_;
    std::vector<double> hourglass_k_;                       // per element (reduced integration)
    std::vector<std::array<const double*, 6>> stress_cols_; // per set: trial stress columns
    long last_unreliable_ = 0; // of the last update, the one commit() accepts
    ContinuumCounters counters_;
};

} // namespace ifsim::fem
