#pragma once
// The material points of one element set: a MaterialPoints<M> of the set's model (one kernel
// per batch), behind a small interface the solver calls once per batch, never per point.
//
// The consistent tangent is the derivative of the integrated update by forward differences,
// the perturbed copies of every point being lanes of one batched update. Two schemes:
//  - adaptive (default): ncomp lanes per point (one per active strain component) integrate
//    adaptively exactly like the base update, so the quotient is the derivative of the very
//    map the residual uses (step sizes vary smoothly with the input). A perturbed lane whose
//    accepted or rejected substep count differs from its base took another step sequence (an
//    accept/reject decision flipped): that point falls back to the rate stiffness (counted).
//  - fixed substeps: 1 + ncomp lanes (base and perturbed copies), all with the base's number
//    of accepted substeps as equal fixed substeps (the engine's point evaluator scheme). Free
//    of step-selection noise, but equal substeps under-resolve what the adaptive steps
//    resolve (the intergranular strain transition), so the tangent is off by O(substep size).
// The cheap alternative is the model's rate stiffness at the committed state in the direction
// of the increment.

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "engine/batched_update.hpp"
#include "engine/model_registry.hpp"
#include "engine/tangent_kind.hpp"

namespace ifsim::fem {

struct TangentSettings {
    TangentKind kind = TangentKind::perturbation;
    double perturbation = 1.0e-7;       // relative to the norm of the point's strain increment
    double perturbation_floor = 1.0e-6; // strain norm used when the increment is smaller
    bool fixed_substeps = false;        // false: adaptive perturbed lanes (see above)
};

struct TangentReport {
    long evaluations = 0; // constitutive evaluations of the perturbation lanes
    long fallbacks = 0;   // points whose perturbed lanes failed or changed their step
                          // sequence: rate stiffness used instead
};

class SetMaterial {
public:
    virtual ~SetMaterial() = default;
    virtual std::string model_name() const = 0;
    virtual int n_state() const = 0;
    virtual std::size_t size() const = 0;

    virtual void set_state(std::size_t i, std::span<const double> y) = 0;
    virtual void set_stress(std::size_t i, const Sym<double>& s) = 0;
    virtual std::vector<double> state(std::size_t i) const = 0; // committed
    virtual std::vector<double> trial_state(std::size_t i) const = 0;

    virtual double* deps(int j) = 0;                  // strain-increment column j (6)
    virtual const double* trial(int k) const = 0;     // trial-state column k
    virtual const double* committed(int k) const = 0; // committed-state column k

    // Trial state = committed state integrated over deps, adaptively.
    virtual UpdateReport update(const UpdateOptions& options) = 0;
    // Tangent of the active components (dim 2: 11 22 12; dim 3: all six) at every point, after
    // update(): out[(i * nc + r) * nc + c] = d sigma_r / d eps_c (tensor components).
    virtual TangentReport tangent(const TangentSettings& settings, const UpdateOptions& options,
                                  int dim, double* out) = 0;
    // Shear modulus of the rate stiffness at the committed state under a zero increment (mean
    // of the shear diagonal / 2): the reference modulus of the hourglass control.
    virtual double shear_modulus(std::size_t i, const UpdateOptions& options) const = 0;
    // Accept the trial states (swap).
    virtual void commit() = 0;

    // Updated Lagrangian (fem/finite_strain.hpp): the next update() integrates from the
    // committed state with its tensors (stress and every history block) turned by the
    // rotation of each point (9 values per point, row-major R: y' = R y R^T). The committed
    // state itself is kept: state() and committed() still give it, and the next call turns
    // it again. A set whose start is never turned runs none of this.
    virtual void rotate_start(const double* rotations) = 0;
};

std::unique_ptr<SetMaterial> make_set_material(const MaterialChoice& material, std::size_t points);

} // namespace ifsim::fem
