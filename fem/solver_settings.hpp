#pragma once
// Inputs of the static solver besides the mesh and the stages: the material of each element
// set, its initial state, and the numerical settings with their documented defaults.

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "engine/batched_update.hpp"
#include "engine/model_registry.hpp"
#include "fem/element_geometry.hpp"
#include "fem/linear_solver.hpp"
#include "fem/set_material.hpp"

namespace ifsim::fem {

// Initial geostatic stress of an element set (applied once, before the first stage):
// sigma_v = -(surcharge + unit_weight * (surface - z)) at each integration point (z the
// vertical coordinate), sigma_h = k0 * sigma_v, no shear. unit_weight 0 gives a uniform
// sigma_v = -surcharge.
struct K0Stress {
    double surface = 0.0;     // vertical coordinate of the ground surface, m
    double unit_weight = 0.0; // gamma, kN/m^3
    double surcharge = 0.0;   // kPa, magnitude of sigma_v at the surface
    double k0 = 0.5;
};

struct ElementSetMaterial {
    std::string element_set;
    MaterialChoice material;
    std::vector<double> initial_state; // the model's flat state (kernels/model_api.hpp)
    double density = 0.0;              // t/m^3: body force rho g under gravity
    std::optional<K0Stress> k0;        // absent: the initial state's stress everywhere
    // Reference shear modulus of the hourglass control (reduced integration), kPa; 0 takes it
    // from the model's rate stiffness at each element's initial state.
    double hourglass_shear_modulus = 0.0;
};

enum class Predictor { extrapolated, tangent, zero };

// How displacements become strains and stresses become forces (fem/continuum_assembly.hpp):
// small strain on the reference configuration, or updated Lagrangian with the Zaremba-Jaumann
// rate (fem/finite_strain.hpp).
enum class Kinematics { small_strain, updated_lagrangian };

struct SolverSettings {
    Kinematics kinematics = Kinematics::small_strain;
    Integration integration = Integration::full;
    // Hourglass stiffness k = c * G_ref * V * sum(bbar^2) per hourglass mode and direction
    // (Flanagan-Belytschko stiffness form; see docs/fem.md for the calibration of c).
    double hourglass_coefficient = 0.05;
    TangentSettings tangent;
    UpdateOptions update;
    LinearSolverKind linear_solver = LinearSolverKind::umfpack;
    // Converged when ||R|| <= residual_tolerance * F_ref and the last correction
    // ||du|| <= displacement_tolerance * ||Delta u||, or when ||R|| <= 1e-2 residual_tolerance
    // * F_ref alone (F_ref = max(||f_ext||, ||f_int|| over all DOFs incl. reactions)).
    double residual_tolerance = 1.0e-8;
    double displacement_tolerance = 1.0e-6;
    double reference_force_floor = 1.0e-12; // kN: keeps F_ref > 0 in an unloaded body
    int max_iterations = 20;
    // First guess of the free DOFs (the prescribed ones start at their new values):
    //   extrapolated  the previous converged increment of the stage scaled to the new length;
    //                 where there is none (a stage's first increment, a retry after a cut) the
    //                 tangent predictor;
    //   tangent       K(u_n) du = R(u_n) - K_fp du_p: the free DOFs follow the prescribed
    //                 ones through the tangent at the committed state (one extra solve);
    //   zero          the free DOFs start where they are.
    // Without the tangent predictor a stage that reverses a prescribed motion starts from a
    // guess where the prescribed body has moved into a soft neighbour alone (docs/fem.md).
    Predictor predictor = Predictor::extrapolated;
    int max_cuts = 6; // halvings of one nominal increment before failing
    // Work bound of one nominal step: the interface models' own substeps, summed over its
    // increments, cuts, Newton iterations and Jacobian lanes, per contact point. A step past it
    // fails the stage at once, naming the bound: cutting would only spend more (a band of 10
    // micrometres in the shear box ran for more than 10 minutes in one step of 0.1 mm). The
    // shear box's whole shear path as one nominal step needs 1.6e7 per point, a normal step
    // about 3000; an interface test's step (one point) is bounded at 1e7.
    double max_step_substeps = 5.0e7;
    // After a cut the increment grows back (doubling, never past the nominal step) once
    // `growth_after` increments in a row converged at the smaller size.
    int growth_after = 2;
    // 0: every nominal step starts at its full size. N > 0: a step starts at the cut depth its
    // predecessor in the stage ended at, and one level coarser once N steps in a row ended at
    // the depth they started at. Where every full-size step of a stage fails first (the fine
    // Sanisand scene: 27 % of its time in failed full-size attempts, up to 300 s for one),
    // the failed attempts are paid once per N + 1 steps instead of in every step.
    int carry_cuts = 0;
    // Backtracking line search: a Newton step whose residual norm is larger than the last is
    // halved up to this many times (0: plain Newton). Needed at kinks of the response (the
    // loading/unloading switch of the intergranular strain) where Newton falls into 2-cycles.
    int max_line_search = 4;
    // Accept an iterate whose relative residual is at most this and has stopped falling (no
    // halving over the last 3 iterations): the floor set by the inner solves (Algorithm 1
    // and the adaptive substeps converge to their own tolerances). Counted. 0: never.
    double stagnation_tolerance = 1.0e-5;
    // Cut an increment whose Newton iteration has diverged: 6 iterations into a solve, its
    // relative residual is still above the one the solve started from (counted:
    // divergence_cuts). Such an iteration rarely recovers within max_iterations, and its
    // iterates cost most: their strains send the interface models into thousands of
    // substeps (docs/fem.md, "Early cuts").
    bool divergence_check = true;
    // Implicit gather of the novel interface's in-plane targets (Eqs. 14-16): after Newton
    // converges, the targets are extrapolated again from the converged continuum stress and,
    // while one moved by more than gather_tolerance (relative), Newton goes on with them, at
    // most max_gathers times, else the increment is cut. 0 gathers: the explicit gather of
    // the paper (targets from the last converged increment; error O(increment)).
    double gather_tolerance = 1.0e-3;
    int max_gathers = 10;
    // Aitken's dynamic relaxation of the gathers that did not settle (fem/aitken_relaxation.hpp):
    // the gather is a fixed-point iteration on the targets, and on the §6 Sanisand runs it
    // contracted by only ~0.8 per round (ten rounds, then a cut at max_gathers).
    bool gather_aitken = false;
    // Early gather: once a Newton solve's relative residual is at most this, the targets are
    // gathered once before it converges; when they moved by more than gather_tolerance the
    // next solve starts there, instead of converging the last digits with targets about to be
    // replaced (on the fine §6 run 1 745 of 4 660 Newton iterations were spent so). The
    // acceptance test is unchanged: converged with settled targets. 0: gather only at
    // convergence.
    double early_gather_residual = 1.0e-5;
    // After an increment that needed the pairs' slip viscosity (the retry at the finest cut),
    // the next increments at the finest cut take it at once instead of failing first without
    // it; the first increment of a coarser size (after growth) or of the next step tries
    // without again. On the fine §6 novel run 47 increments in a row of gravity stage 3 each
    // failed without it first (278 of 1 314 s; docs/large-scale-test.md, session 26).
    bool hold_slip_viscosity = false;
    std::size_t element_grain = 64; // elements per task in the element loops
    // Diagnostic: at every Newton iteration compare the tangent with central differences of
    // the residual along the Newton direction (fem/tangent_check.cpp; costs 4 residual
    // passes per iteration). The records are kept by the solver.
    bool check_tangent = false;
    // Solve each Newton system by GMRES with the last factorisation as its preconditioner,
    // and factorise anew only when GMRES does not converge within krylov_max_iterations
    // steps. The tangent changes little between iterations, and a factorisation with the copy
    // of its factors costs about 30 preconditioner applications on the fine §6 mesh
    // (docs/fem.md, "Reused factorisations"); a failed GMRES is not allowed to cost more than
    // that (at 20 steps half of the failures there were projected within 7 more steps of the
    // tolerance, two thirds within 11; docs/performance.md, "Preconditioner solves"). GMRES stops
    // at a relative residual of min(krylov_tolerance, r) of the linear system, r the Newton
    // iteration's relative residual. Measured on the coarse §6 run: 1e-10 reaches the direct
    // solves' history; 1e-4 (an inexact-Newton forcing term) stalled Newton at 1e-4 in gravity
    // stage 2 - the penalty-stiff system amplifies the linear residual into the correction.
    bool reuse_factorisation = false;
    double krylov_tolerance = 1.0e-10;
    int krylov_max_iterations = 30;
    // The cost of a factorisation in preconditioner applications, for the decision to keep
    // the held one (fem/static_solver.cpp, solve_tangent_system). A count, not a timing, so
    // the run's path does not depend on the machine's load.
    double krylov_factorisation_cost = 30.0;
    // The precision the factors are copied in for GMRES's preconditioner solves (the direct
    // solve after a factorisation is UMFPACK's own). Single streams fewer bytes, and GMRES
    // still solves to krylov_tolerance; double is the default because the fine novel §6 run
    // failed in gravity stage 2 on single's path and passed on double's (docs/fem.md).
    LuPrecision preconditioner_precision = LuPrecision::double_precision;
};

} // namespace ifsim::fem
