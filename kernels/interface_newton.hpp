#pragma once
// One sub-increment of Algorithm 1 (paper §3.5, lines 3-10): a Newton iteration on the
// interface normal strains (Eqs. 21-23) that drives the interface normal stresses to their
// targets (Eqs. 18-20), with the shear strain of the sub-increment prescribed (Eq. 27). Lanes
// converge independently under masks.

#include <array>

#include "kernels/interface_settings.hpp"
#include "kernels/material_update.hpp"
#include "kernels/small_solve.hpp"

namespace ifsim {

// Number of normal-strain unknowns: Stutz: eps_N; novel 2D: eps_N, eps_p1; novel 3D: all three.
inline int interface_unknowns(const InterfaceSettings& s) {
    return s.formulation == InterfaceFormulation::stutz ? 1 : (s.ndim == 2 ? 2 : 3);
}

template <class T, int NS>
struct SubincrementResult {
    StateVec<T, NS> y;
    std::array<T, 3> x{T(0.0), T(0.0), T(0.0)}; // converged normal strain increments
    simd::mask_t<T> converged{};
    simd::mask_t<T> model_failed{};
    simd::mask_t<T> singular{}; // the Newton matrix (Eq. 22) could not be solved
    T residual = T(0.0);
};

// The strain increment of one Newton iterate: normal parts from x, shear from the
// sub-increment of shear strain (tensor components gamma/2), Eq. 27.
template <class T>
Sym<T> interface_strain_increment(int k, const std::array<T, 3>& x, const T& dgam1,
                                  const T& dgam2) {
    return {x[0], k >= 2 ? x[1] : T(0.0), k >= 3 ? x[2] : T(0.0), 0.5 * dgam1, 0.5 * dgam2, T(0.0)};
}

// One sub-increment: Newton on the normal strains from y0 (Algorithm 1 lines 3-10). Lanes in
// `perturbed` take the perturbation Jacobian whatever s.newton_jacobian says (a lane's second
// try, interface_step).
template <class M, class T>
SubincrementResult<T, M::n_state>
solve_subincrement(const typename M::Params& mp, const InterfaceSettings& s,
                   const StateVec<T, M::n_state>& y0, const std::array<T, 3>& x_guess,
                   const T& dgam1, const T& dgam2, const std::array<T, 3>& target,
                   const simd::mask_t<T>& active, InterfaceStats<T>& stats,
                   const simd::mask_t<T>& perturbed = simd::mask_t<T>(false)) {
    using Mask = simd::mask_t<T>;
    constexpr int NS = M::n_state;
    const int k = interface_unknowns(s);
    T ref = target[0] * target[0];
    for (int c = 1; c < k; ++c) {
        ref += target[c] * target[c];
    }
    ref = simd::max(simd::sqrt(ref), T(1.0e-3));

    SubincrementResult<T, NS> out;
    out.y = y0;
    out.converged = !active;
    out.model_failed = Mask(false);
    out.singular = Mask(false);
    std::array<T, 3> x = x_guess;
    const SubstepControl<T> adaptive_ctl{};
    Mask failed(false); // lanes whose model update or Newton matrix failed
    // Lanes below the tolerance that still take their polishing corrections.
    T polish_left = T(static_cast<double>(s.polish_iterations));
    Mask met(false);
    // Lanes that left the rate Jacobian (newton_switch_ratio) for Broyden updates or the
    // perturbation Jacobian (newton_switch_broyden).
    const bool may_switch =
        s.newton_jacobian == NewtonJacobian::rate && s.newton_switch_ratio > 0.0;
    Mask switched(false);
    T r_before = T(0.0);
    // Broyden's update needs the last iterate, residual and Jacobian of each lane.
    std::array<T, 3> x_last{T(0.0), T(0.0), T(0.0)}, res_last{T(0.0), T(0.0), T(0.0)};
    std::array<std::array<T, 3>, 3> J_last{};
    const bool broyden = may_switch && s.newton_switch_broyden;
    // Backtracking (newton_line_search): the last accepted iterate, its residual and the
    // Newton correction taken from it, and the fraction of that correction being tried.
    const bool search = s.newton_line_search > 0;
    const T max_halvings = T(static_cast<double>(s.newton_line_search));
    std::array<T, 3> x_acc = x, d{T(0.0), T(0.0), T(0.0)};
    T r_acc = T(0.0), lambda = T(1.0), halvings = T(0.0);
    Mask stepped(false);
    for (int it = 0; it <= s.max_newton_iterations + s.polish_iterations; ++it) {
        const Mask working = active && !out.converged && !failed;
        if (simd::none(working)) {
            break;
        }
        const Sym<T> de = interface_strain_increment(k, x, dgam1, dgam2);
        StateVec<T, NS> yt = y0;
        UpdateStats<T> ms;
        material_update<M, T>(mp, s.model, adaptive_ctl, yt, de, ms);
        stats.evaluations += simd::select(working, T(1.0), T(0.0));
        stats.model_substeps += simd::select(working, ms.substeps, T(0.0));

        std::array<T, 3> res{T(0.0), T(0.0), T(0.0)};
        T r2 = T(0.0);
        for (int c = 0; c < k; ++c) {
            res[c] = yt[c] - target[c];
            r2 += res[c] * res[c];
        }
        const T r = simd::sqrt(r2) / ref;
        const Mask model_ok = ms.status > -0.5;
        // A trial that does not lower the residual (or whose model update failed) goes back
        // to half its step; it takes no part in what follows.
        const Mask back = search ? (working && stepped && !met && (!model_ok || !(r < r_acc)) &&
                                    (halvings < max_halvings))
                                 : Mask(false);
        if (may_switch && it > 0) {
            switched = switched || (working && !back && model_ok && !met && (r >= s.tolerance) &&
                                    (r > T(s.newton_switch_ratio) * r_before));
        }
        r_before = simd::select(working && !back, r, r_before);
        // The iterate that first meets the tolerance is the result unless a polishing
        // correction ends below the tolerance too: a correction that leaves it (a wild step
        // from a poor Jacobian) must not replace a converged state.
        const Mask first_met = working && !back && model_ok && !met && (r < s.tolerance);
        met = met || first_met;
        out.y = select_state<T, NS>(first_met, yt, out.y);
        for (int c = 0; c < 3; ++c) {
            out.x[c] = simd::select(first_met, x[c], out.x[c]);
        }
        out.residual = simd::select(first_met, r, out.residual);
        const Mask now = working && met && (polish_left < 0.5 || !model_ok);
        const Mask polished = now && !first_met && model_ok && (r < s.tolerance);
        out.y = select_state<T, NS>(polished, yt, out.y);
        for (int c = 0; c < 3; ++c) {
            out.x[c] = simd::select(polished, x[c], out.x[c]);
        }
        out.residual = simd::select(polished, r, out.residual);
        out.converged = out.converged || now;
        failed = failed || (working && !back && !model_ok && !met);
        out.model_failed = out.model_failed || (working && !back && !model_ok && !met);
        const Mask iterate = working && !back && !now && model_ok;
        polish_left = simd::select(iterate && met, polish_left - 1.0, polish_left);
        if (simd::none(iterate || back) || it == s.max_newton_iterations + s.polish_iterations) {
            // Lanes that met the tolerance but ran out of iterations keep their last iterate
            // if it is still below the tolerance, else the one that met it.
            const Mask take = iterate && met && !first_met && (r < s.tolerance);
            out.y = select_state<T, NS>(take, yt, out.y);
            for (int c = 0; c < 3; ++c) {
                out.x[c] = simd::select(take, x[c], out.x[c]);
            }
            out.converged = out.converged || (iterate && met);
            out.residual = simd::select(take || (iterate && !met), r, out.residual);
            out.residual = simd::select(back, r_acc, out.residual); // where it stood
            break;
        }
        if (search && simd::any(back)) {
            lambda = simd::select(back, 0.5 * lambda, lambda);
            halvings = simd::select(back, halvings + 1.0, halvings);
            for (int c = 0; c < k; ++c) {
                x[c] = simd::select(back, x_acc[c] - lambda * d[c], x[c]);
            }
            if (simd::none(iterate)) {
                continue;
            }
        }

        // Jacobian d sigma_normal / d eps_normal (Eq. 22).
        const Mask by_broyden = s.newton_switch_broyden ? (switched && !perturbed) : Mask(false);
        const Mask by_difference = s.newton_jacobian == NewtonJacobian::perturbation
                                       ? Mask(true)
                                       : (perturbed || (switched && !by_broyden));
        std::array<std::array<T, 3>, 3> J{};
        if (!simd::all(by_difference || !iterate)) {
            const auto cols = M::template rate_stiffness<T>(mp, s.model, y0, de);
            for (int rr = 0; rr < k; ++rr) {
                for (int c = 0; c < k; ++c) {
                    J[rr][c] = cols[c][rr];
                }
            }
        }
        const Mask differenced = iterate && by_difference;
        if (simd::any(differenced)) {
            // Same number of equal substeps as the base, so the quotient sees no step noise.
            SubstepControl<T> fixed;
            fixed.fixed_substeps = simd::max(ms.substeps, T(1.0));
            const T delta = s.newton_perturbation * simd::max(voigt::norm(de), T(1.0e-9));
            StateVec<T, NS> yb = y0;
            UpdateStats<T> bs;
            material_update<M, T>(mp, s.model, fixed, yb, de, bs);
            stats.evaluations += simd::select(differenced, T(1.0), T(0.0));
            stats.model_substeps += simd::select(differenced, bs.substeps, T(0.0));
            for (int c = 0; c < k; ++c) {
                Sym<T> dp = de;
                dp[c] += delta;
                StateVec<T, NS> yp = y0;
                UpdateStats<T> ps;
                material_update<M, T>(mp, s.model, fixed, yp, dp, ps);
                stats.evaluations += simd::select(differenced, T(1.0), T(0.0));
                stats.model_substeps += simd::select(differenced, ps.substeps, T(0.0));
                for (int rr = 0; rr < k; ++rr) {
                    J[rr][c] = simd::select(by_difference, (yp[rr] - yb[rr]) / delta, J[rr][c]);
                }
            }
        }
        if (simd::any(iterate && by_broyden)) {
            // J = J_last + (dr - J_last dx) dx^T / dx^T dx, from the last step of this lane.
            std::array<T, 3> dx{}, u{};
            T dxx = T(0.0);
            for (int c = 0; c < k; ++c) {
                dx[c] = x[c] - x_last[c];
                dxx += dx[c] * dx[c];
            }
            for (int rr = 0; rr < k; ++rr) {
                T Jdx = T(0.0);
                for (int c = 0; c < k; ++c) {
                    Jdx += J_last[rr][c] * dx[c];
                }
                u[rr] = (res[rr] - res_last[rr]) - Jdx;
            }
            const Mask usable = iterate && by_broyden && (dxx > T(1.0e-300));
            const T inv = T(1.0) / simd::select(usable, dxx, T(1.0));
            for (int rr = 0; rr < k; ++rr) {
                for (int c = 0; c < k; ++c) {
                    J[rr][c] = simd::select(usable, J_last[rr][c] + u[rr] * dx[c] * inv, J[rr][c]);
                }
            }
        }
        for (int rr = 0; rr < k && broyden; ++rr) {
            x_last[rr] = simd::select(iterate, x[rr], x_last[rr]);
            res_last[rr] = simd::select(iterate, res[rr], res_last[rr]);
            for (int c = 0; c < k; ++c) {
                J_last[rr][c] = simd::select(iterate, J[rr][c], J_last[rr][c]);
            }
        }
        const SmallSolve<T> sol = small_solve<T>(k, J, res);
        // A lane that met the tolerance and cannot take its polishing correction keeps the
        // iterate that met it.
        const Mask unsolved = iterate && !sol.solved;
        out.converged = out.converged || (unsolved && met);
        failed = failed || (unsolved && !met);
        // A failed lane reports where it stood (a residual of 0 would say nothing).
        out.singular = out.singular || (unsolved && !met);
        out.residual = simd::select(unsolved && !met, r, out.residual);
        const Mask step = iterate && sol.solved;
        if (search) {
            for (int c = 0; c < k; ++c) {
                x_acc[c] = simd::select(step, x[c], x_acc[c]);
                d[c] = simd::select(step, sol.x[c], d[c]);
            }
            r_acc = simd::select(step, r, r_acc);
            lambda = simd::select(step, T(1.0), lambda);
            halvings = simd::select(step, T(0.0), halvings);
            stepped = stepped || step;
        }
        for (int c = 0; c < k; ++c) {
            x[c] = simd::select(step, x[c] - sol.x[c], x[c]);
        }
        stats.newton_iterations += simd::select(step, T(1.0), T(0.0));
    }
    return out;
}

} // namespace ifsim
