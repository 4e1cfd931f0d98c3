#pragma once
// The batched update of contact points: every point runs Algorithm 1 for its base evaluation
// and, for the Jacobian, for its perturbed evaluations (paper Eq. 37, theta = `perturbation`). The
// perturbed evaluations are lanes like the base ones: a point expands into L lanes of a lane
// buffer; TBB runs chunks of points, xsimd runs across lanes, packed into batches by expected work
// (engine/contact_lanes.hpp). Results are bitwise independent of the thread count (fixed chunks,
// per-point results, reductions in point order).
//
// Jacobian schemes:
//   perturbation       Eq. 37, forward differences of the whole Algorithm 1 (state not perturbed)
//                      for every slave and master displacement: 2 ndim + 1 evaluations.
//   perturbation-one-side  Eq. 37 on one side only: ndim + 1 evaluations. The traction of a
//                      point depends on the two sides only through the gap (slave +, master -),
//                      so the other side's columns are the perturbed side's negated (chain
//                      rule). Not the default: forward and backward differences differ by up to
//                      100 % at small shear increments, and the mix of both in `perturbation`
//                      carried the coarse Stutz scene of paper §6 through gravity where this
//                      one diverges (docs/interface.md).
//   full-perturbation  Eqs. 39-40. They add the dependence of the contact stress t and the state
//                      k that an evaluation starts from on the displacement. Here every
//                      evaluation starts from the converged state of the last increment and
//                      carries tau from its own last converged sub-increment (Eq. 24), so that
//                      start state does not depend on the current displacement: J and G of the
//                      start state vanish, the fixed point of Eqs. 39-40 is reached at once and
//                      the columns equal Eq. 37's (docs/interface.md). An earlier version shifted
//                      the start state by theta times the derivative of the END state, which
//                      counted the dependence twice (columns about 2x too large).
//   analytical         Eq. B3: rate stiffness of the model times d eps / d g (first term of B2)
//   central            the lanes of Eq. 37, combined: the slave lane of a local axis moves the
//                      gap by +theta, the master lane of the same axis by -theta, and the
//                      tractions depend on the two sides only through the gap, so
//                      (t(+theta) - t(-theta)) / 2 theta is the derivative for both (slave: +,
//                      master: -) to O(theta^2) at no extra cost. Eq. 37's forward differences
//                      carry theta |t''| / 2, large where the normal perturbation is a sizeable
//                      part of t_N (docs/interface.md).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "engine/contact_lanes.hpp"
#include "engine/contact_points.hpp"
#include "engine/parallel_chunks.hpp"
#include "kernels/interface_algorithm1.hpp"

namespace ifsim {

enum class ContactJacobian : int {
    perturbation = 0,
    full_perturbation = 1,
    analytical = 2,
    central = 3,
    perturbation_one_side = 4
};

// The scene names of ContactJacobian, indexed by its value.
inline constexpr std::array<std::string_view, 5> contact_jacobian_names = {
    "perturbation", "full-perturbation", "analytical", "central", "perturbation-one-side"};

// The scheme of a scene name; false for an unknown name.
inline bool contact_jacobian_from_name(std::string_view name, ContactJacobian& out) {
    for (std::size_t k = 0; k < contact_jacobian_names.size(); ++k) {
        if (contact_jacobian_names[k] == name) {
            out = static_cast<ContactJacobian>(k);
            return true;
        }
    }
    return false;
}

struct ContactOptions {
    bool simd = true;
    std::size_t chunk_points = 32; // points per TBB task (rounded up to the lane width)
    // A small point set is still split into at least this many tasks (down to one SIMD batch
    // each), its base lanes and its perturbed lanes in tasks of their own, so that a refined
    // 2D box of 16 points runs on two cores. The split depends on the point count only, never on
    // the thread count.
    std::size_t min_tasks = 8;
    InterfaceSettings interface;
    ContactJacobian jacobian = ContactJacobian::perturbation;
    double perturbation = 1.4901161193847656e-8; // theta = sqrt(machine epsilon), Eq. 38
};

struct ContactReport {
    std::size_t points = 0;
    std::size_t failed = 0;
    std::size_t first_failed = std::numeric_limits<std::size_t>::max();
    double first_failed_residual = 0.0;
    double first_failed_cause = 0.0; // interface_failure code
    std::size_t band_clamped = 0;    // points whose d_s was held at its floor
    double dropped_columns = 0.0;    // failed Jacobian lanes (their point took Eq. B3's columns)
    std::size_t open = 0;
    double lanes = 0.0;         // evaluations of Algorithm 1 (base + perturbed)
    double subincrements = 0.0; // base lanes
    double newton_iterations = 0.0;
    double constitutive_evaluations = 0.0; // every model update, perturbed lanes included
    double model_substeps = 0.0;
    double newton_fallbacks = 0.0; // calls that took Algorithm 1's second try
    bool ok() const { return failed == 0; }
};

// A failed interface point's cause in words, with its number where one goes with it:
// "Newton on ... did not converge (Eqs. 18-20) (Algorithm 1 residual 0.989)".
inline std::string describe_interface_failure(double cause, double residual) {
    const std::string label = interface_failure::residual_label(cause);
    return label.empty()
               ? std::string(interface_failure::describe(cause))
               : fmt::format("{} ({} {:.3g})", interface_failure::describe(cause), label, residual);
}

// The lane blocks of one update: block 0 the base, then `perturbed` blocks along the local axes
// (both sides: slave +theta e_a for every axis a, then master +theta e_a; one side: one block
// per axis, the side given by axis()), then with adaptive sub-increments the base re-run on the
// perturbed lanes' discretisation.
struct ContactLaneBlocks {
    int perturbed = 0;
    bool both_sides = false;
    bool rerun = false;
    int blocks = 1;
    int ref = 0; // the reference of the differences: the re-run, or the base

    ContactLaneBlocks(const ContactOptions& opt, int ndim) {
        both_sides = opt.jacobian != ContactJacobian::perturbation_one_side;
        perturbed = opt.jacobian == ContactJacobian::analytical ? 0 : both_sides ? 2 * ndim : ndim;
        rerun = perturbed > 0 && opt.interface.adaptive;
        blocks = 1 + perturbed + (rerun ? 1 : 0);
        ref = rerun ? blocks - 1 : 0;
    }

    // Block k: the local axis it perturbs and the sign of the gap change (slave moved along
    // the axis: +, master moved: -); -1 for the base and the re-run. With one side, the normal
    // is perturbed on the slave and the tangents on the master: the lanes whose columns the
    // point-level interface test reads (engine/interface_points.hpp), so its runs are the same
    // with either scheme.
    int axis(int k, int ndim, double& sign) const {
        sign = 0.0;
        if (k == 0 || k > perturbed) {
            return -1;
        }
        const bool slave = both_sides ? k <= ndim : k == 1;
        sign = slave ? 1.0 : -1.0;
        return k <= ndim ? k - 1 : k - 1 - ndim;
    }
};

// The points per TBB task: `chunk_points`, or fewer for a small set so that it makes at least
// `min_tasks` tasks; always a multiple of the lane width.
inline std::size_t contact_chunk_points(std::size_t points, const ContactOptions& opt,
                                        std::size_t lane_width) {
    const std::size_t tasks = std::max<std::size_t>(opt.min_tasks, 1);
    const std::size_t wanted = std::min(opt.chunk_points, (points + tasks - 1) / tasks);
    return std::max<std::size_t>(1, (wanted + lane_width - 1) / lane_width) * lane_width;
}

// The lanes per TBB task of the perturbed-lane queue: as many as `chunk_points` points carry
// (`per_point` lanes each), or fewer so that a small queue makes at least `min_tasks` tasks;
// always a multiple of the lane width.
inline std::size_t contact_chunk_lanes(std::size_t lanes, const ContactOptions& opt,
                                       std::size_t per_point, std::size_t lane_width) {
    const std::size_t tasks = std::max<std::size_t>(opt.min_tasks, 1);
    const std::size_t full = opt.chunk_points * std::max<std::size_t>(per_point, 1);
    const std::size_t wanted = std::min(full, (lanes + tasks - 1) / tasks);
    return std::max<std::size_t>(1, (wanted + lane_width - 1) / lane_width) * lane_width;
}

// Batched contact update with Jacobian columns.
//
// Lane layout: block k of the lane buffer holds lanes [k P, (k+1) P) (ContactLaneBlocks). Each
// point's perturbed lanes (and that re-run) take exactly the number of equal sub-increments its
// base accepted, so the forward differences of Eq. 37 see no change of discretisation, only the
// perturbation. The buffer is allocated once and reused.
template <class M>
class ContactEngine {
public:
    static constexpr int NS = M::n_state;

    ContactReport update(ContactPoints<M>& cp, const typename M::Params& mp,
                         const ContactOptions& opt) {
        const int ndim = cp.ndim();
        const ContactLaneBlocks layout(opt, ndim);
        const bool rerun = layout.rerun;
        const int blocks = layout.blocks;
        const int ref = layout.ref;
        const std::size_t P = cp.padded();
        const int n_cols = detail::lane_col::state + ContactPoints<M>::n_state_cols;
        if (lanes_.columns() != n_cols || lanes_.length() != P * blocks) {
            ColumnStore fresh(n_cols, P * blocks);
            lanes_.swap(fresh);
        }
        const std::size_t chunk = contact_chunk_points(cp.size(), opt, simd::lanes);

        if (order_.size() != P * blocks) {
            order_.assign(P * blocks, detail::LaneKey{});
        }
        // The Jacobian lanes of an adaptive run have a reference lane of their own (the base
        // re-run on their discretisation), so they may solve Algorithm 1 more tightly than the
        // base: InterfaceSettings::jacobian_tolerance.
        InterfaceSettings lane_settings = opt.interface;
        if (rerun && opt.interface.jacobian_tolerance > 0.0) {
            lane_settings.tolerance = opt.interface.jacobian_tolerance;
            lane_settings.newton_jacobian = NewtonJacobian::perturbation;
        }
        auto execute = [&](const detail::LaneKey* keys, std::size_t n, const InterfaceSettings& s) {
            if (opt.simd) {
                detail::run_lanes_packed<M>(mp, s, lanes_, {keys, n});
            } else {
                detail::run_lanes_scalar<M>(mp, s, lanes_, {keys, n});
            }
        };
        // A base lane held to equal sub-increments (contact_col::forced) that took exactly
        // that many is its own reference re-run: same inputs, same discretisation, same
        // settings, and a lane's bits do not depend on its batch. Such reference lanes are
        // copied instead of run.
        const bool same_settings = !(opt.interface.jacobian_tolerance > 0.0);
        reference_copied_.assign(P, 0);
        // 1. The base lanes of the whole set, ordered by their expected work so that lanes of
        //    equal work share batches, run in tasks of `chunk` lanes. The perturbed lanes take
        //    their sub-increment counts from them.
        detail::LaneKey* base_keys = order_.data();
        for_chunks(P, chunk, [&](std::size_t b, std::size_t e) {
            for (std::size_t i = b; i < e; ++i) {
                base_keys[i].lane = i;
            }
            gather(cp, opt, layout, P, 0, ndim, b, e);
            if (opt.simd) {
                detail::estimate_work<M>(opt.interface, lanes_, base_keys + b, e - b);
            }
        });
        if (opt.simd) {
            detail::sort_by_work(base_keys, P);
        }
        for_chunks(P, chunk, [&](std::size_t b, std::size_t e) {
            execute(base_keys + b, e - b, opt.interface);
        });
        // 2. Every perturbed lane (and re-run) of the set as one queue, ordered by work, in
        //    tasks of lanes. Per chunk of points, a point whose lanes cost several times the
        //    others' kept one core busy while the other waited (the refined 2D box:
        //    docs/performance.md, "Small point sets on two cores").
        for_chunks(P, chunk, [&](std::size_t b, std::size_t e) {
            for (int k = 1; k < blocks; ++k) {
                gather(cp, opt, layout, P, k, ndim, b, e);
            }
        });
        detail::LaneKey* lane_keys = order_.data() + P;
        std::size_t queued = 0;
        for (int k = 1; k < blocks; ++k) {
            for (std::size_t i = 0; i < P; ++i) {
                if (k == ref && rerun && same_settings && base_is_reference(i)) {
                    reference_copied_[i] = 1;
                    continue;
                }
                lane_keys[queued++].lane = k * P + i;
            }
        }
        const std::size_t lane_task =
            contact_chunk_lanes(queued, opt, static_cast<std::size_t>(blocks - 1), simd::lanes);
        if (opt.simd) {
            for_chunks(queued, lane_task, [&](std::size_t b, std::size_t e) {
                detail::estimate_work<M>(lane_settings, lanes_, lane_keys + b, e - b);
            });
            detail::sort_by_work(lane_keys, queued);
        }
        for_chunks(queued, lane_task, [&](std::size_t b, std::size_t e) {
            execute(lane_keys + b, e - b, lane_settings);
        });
        // 3. The results back to the points.
        for_chunks(P, chunk, [&](std::size_t b, std::size_t e) {
            for (std::size_t i = b; i < e; ++i) {
                if (reference_copied_[i] != 0) {
                    copy_base_to_reference(P, ref, i);
                }
            }
            scatter(cp, mp, opt, layout, P, b, e);
        });

        ContactReport rep;
        rep.points = cp.size();
        for (std::size_t i = 0; i < cp.size(); ++i) {
            if (cp.output(contact_col::status)[i] < -0.5) {
                ++rep.failed;
                if (i < rep.first_failed) {
                    rep.first_failed = i;
                    rep.first_failed_residual = cp.output(contact_col::residual)[i];
                    rep.first_failed_cause = cp.output(contact_col::cause)[i];
                }
            }
            rep.open += cp.output(contact_col::open)[i] > 0.5 ? 1 : 0;
            rep.band_clamped += cp.output(contact_col::band_clamped)[i] > 0.5 ? 1 : 0;
            rep.dropped_columns += cp.output(contact_col::dropped_columns)[i];
            rep.subincrements += cp.output(contact_col::subincrements)[i];
            rep.newton_iterations += cp.output(contact_col::newton_iterations)[i];
            rep.constitutive_evaluations += cp.output(contact_col::evaluations)[i];
            rep.model_substeps += cp.output(contact_col::model_substeps)[i];
            rep.newton_fallbacks += cp.output(contact_col::newton_fallbacks)[i];
        }
        rep.lanes = static_cast<double>(cp.size()) * blocks;
        for (std::size_t i = 0; i < cp.size(); ++i) {
            rep.lanes -= reference_copied_[i];
        }
        return rep;
    }

private:
    // The perturbations of Eq. 37 are taken along the point's local axes (n, t1, t2) and turned
    // into the global columns afterwards, so that each axis gets a size of its own: theta
    // (Eq. 38) along the tangents, and along the normal at most 1 % of the normal traction
    // through the penalty. theta k_N is 1.5 kPa for k_N = 1e8 kPa/m: near opening that moved
    // the perturbed lane across t_N = 0 and its column was the secant to an open contact.
    static double axis_theta(const ContactPoints<M>& cp, const ContactOptions& opt, std::size_t i,
                             int axis) {
        if (axis != 0) {
            return opt.perturbation;
        }
        const double k_N = cp.input(contact_col::k_N)[i];
        const double t_N = std::abs(cp.input(contact_col::t_N)[i]);
        const double floor = opt.interface.open_threshold;
        return k_N > 0.0 ? std::min(opt.perturbation, 0.01 * std::max(t_N, floor) / k_N)
                         : opt.perturbation;
    }

    void gather(ContactPoints<M>& cp, const ContactOptions& opt, const ContactLaneBlocks& layout,
                std::size_t P, int k, int ndim, std::size_t b, std::size_t e) {
        using namespace detail::lane_col;
        for (std::size_t i = b; i < e; ++i) {
            const std::size_t l = k * P + i;
            double sign = 0.0;
            const int axis = layout.axis(k, ndim, sign);
            double local[3] = {0.0, 0.0, 0.0}; // gap change along n, t1, t2
            if (axis >= 0) {
                local[axis] = sign * axis_theta(cp, opt, i, axis);
            }
            const double dgn = local[0], dg_t1 = local[1], dg_t2 = local[2];
            // Normal: t_N = k_N g_N. Tangential (Eq. A13): master minus slave motion.
            lanes_.col(t_N)[l] =
                cp.input(contact_col::t_N)[i] + cp.input(contact_col::k_N)[i] * dgn;
            lanes_.col(dg1)[l] = cp.input(contact_col::dg1)[i] - dg_t1;
            lanes_.col(dg2)[l] = cp.input(contact_col::dg2)[i] - dg_t2;
            // Targets tied to t_N (bounds, relaxation) follow the normal perturbation.
            const double dtn = cp.input(contact_col::k_N)[i] * dgn;
            lanes_.col(s_p1)[l] =
                cp.input(contact_col::s_p1)[i] + cp.input(contact_col::dsp1_dtn)[i] * dtn;
            lanes_.col(s_p2)[l] =
                cp.input(contact_col::s_p2)[i] + cp.input(contact_col::dsp2_dtn)[i] * dtn;
            // Perturbed lanes follow their base's discretisation.
            lanes_.col(forced)[l] = k == 0 ? cp.input(contact_col::forced)[i]
                                           : std::max(1.0, lanes_.col(subincrements)[i]);
            for (int c = 0; c < ContactPoints<M>::n_state_cols; ++c) {
                lanes_.col(state + c)[l] = cp.committed(c)[i];
            }
        }
    }

    bool base_is_reference(std::size_t i) const {
        using namespace detail::lane_col;
        const double held = lanes_.col(forced)[i];
        return held > 0.5 && lanes_.col(status)[i] > -0.5 && lanes_.col(subincrements)[i] == held;
    }

    // The reference lane takes the base lane's inputs, state and results; it did no work.
    void copy_base_to_reference(std::size_t P, int ref, std::size_t i) {
        using namespace detail::lane_col;
        const std::size_t l = static_cast<std::size_t>(ref) * P + i;
        for (int c = 0; c < lanes_.columns(); ++c) {
            lanes_.col(c)[l] = lanes_.col(c)[i];
        }
        lanes_.col(evaluations)[l] = 0.0;
        lanes_.col(msub)[l] = 0.0;
        lanes_.col(newton)[l] = 0.0;
        lanes_.col(fallbacks)[l] = 0.0;
    }

    double lane_traction(std::size_t l, int comp) const {
        using namespace detail::lane_col;
        if (lanes_.col(open)[l] > 0.5) {
            // Open (t_N above -open_threshold): the penalty's normal traction, and the band's
            // shear scaled with t_N / sigma_N. A touching point's band was integrated at
            // sigma_N = -threshold (interface_begin), so the traction fades to zero with t_N
            // and equals the closed branch's at the threshold (a jump there makes the global
            // Newton chatter between open and closed); a separated one (t_N >= 0) gives 0.
            const double tn = std::min(0.0, lanes_.col(t_N)[l]);
            if (comp == 0) {
                return tn;
            }
            const double sn = lanes_.col(state + 0)[l];
            const double ratio = sn < 0.0 ? std::clamp(tn / sn, 0.0, 1.0) : 0.0;
            return ratio * lanes_.col(state + (comp == 1 ? 3 : 4))[l];
        }
        return comp == 0 ? lanes_.col(t_N)[l] : lanes_.col(state + (comp == 1 ? 3 : 4))[l];
    }

    void scatter(ContactPoints<M>& cp, const typename M::Params& mp, const ContactOptions& opt,
                 const ContactLaneBlocks& layout, std::size_t P, std::size_t b, std::size_t e) {
        using namespace detail::lane_col;
        const int ndim = cp.ndim();
        const int n_pert = layout.perturbed;
        const int blocks = layout.blocks;
        const int ref = layout.ref;
        for (std::size_t i = b; i < e; ++i) {
            // The point's status is its base lane's. A perturbed lane that fails while the base
            // succeeded (e.g. a normal perturbation closing an open contact at t_N ~ 0) is
            // counted and the point takes the analytical columns instead of failing.
            const double st = lanes_.col(status)[i];
            const double why = lanes_.col(cause)[i];
            double evals = 0.0;
            double dropped = 0.0;
            double fallbacks_all = 0.0;
            for (int k = 0; k < blocks; ++k) {
                evals += lanes_.col(evaluations)[k * P + i];
                fallbacks_all += lanes_.col(fallbacks)[k * P + i];
                if (k > 0 && lanes_.col(status)[k * P + i] < -0.5) {
                    dropped += 1.0;
                }
            }
            for (int c = 0; c < ContactPoints<M>::n_state_cols; ++c) {
                cp.trial(c)[i] = lanes_.col(state + c)[i];
            }
            for (int comp = 0; comp < 3; ++comp) {
                cp.output(contact_col::traction + comp)[i] = lane_traction(i, comp);
            }
            // A point whose base succeeded but whose reference or perturbed lanes failed (a
            // lane that cannot be integrated with the base's equal sub-increments, e.g. at a
            // reversal) takes the analytical columns of Eq. B3: the exact penalty row and the
            // model's rate stiffness in shear. Zero columns dropped the penalty row with them
            // and left the global Newton without the normal stiffness of the point.
            if (n_pert > 0 && dropped > 0.0 && st > -0.5) {
                analytical_jacobian(cp, mp, opt, i);
            } else if (n_pert > 0) {
                // Columns along the local axes, then turned into the global directions:
                // d t / d u_d = sum over axes a of (d t / d u along a) (e_a)_d.
                const bool ref_ok = lanes_.col(status)[ref * P + i] > -0.5;
                double local[3][6] = {};
                const bool central = opt.jacobian == ContactJacobian::central;
                for (int k = 1; k <= n_pert; ++k) {
                    const bool usable = ref_ok && lanes_.col(status)[k * P + i] > -0.5;
                    double sign = 0.0;
                    const int axis = layout.axis(k, ndim, sign);
                    const double th = axis_theta(cp, opt, i, axis);
                    const int slot = sign > 0.0 ? axis : ndim + axis; // slave or master column
                    for (int comp = 0; comp < 3; ++comp) {
                        local[comp][slot] = usable ? (lane_traction(k * P + i, comp) -
                                                      lane_traction(ref * P + i, comp)) /
                                                         th
                                                   : 0.0;
                    }
                }
                for (int a = 0; central && a < ndim; ++a) {
                    // Slave lane: +theta on the gap, master lane: -theta. Where one of the two
                    // failed its forward difference is zero; keep the other one-sided.
                    const bool s_ok = lanes_.col(status)[(1 + a) * P + i] > -0.5;
                    const bool m_ok = lanes_.col(status)[(1 + ndim + a) * P + i] > -0.5;
                    for (int comp = 0; comp < 3 && s_ok && m_ok; ++comp) {
                        const double d = 0.5 * (local[comp][a] - local[comp][ndim + a]);
                        local[comp][a] = d;
                        local[comp][ndim + a] = -d;
                    }
                }
                for (int a = 0; !layout.both_sides && a < ndim; ++a) {
                    // One side perturbed: the other side's column of the axis is its negative.
                    const bool slave_run = a == 0; // as ContactLaneBlocks::axis chose
                    for (int comp = 0; comp < 3; ++comp) {
                        if (slave_run) {
                            local[comp][ndim + a] = -local[comp][a];
                        } else {
                            local[comp][a] = -local[comp][ndim + a];
                        }
                    }
                }
                const int axes[3] = {contact_col::n, contact_col::t1, contact_col::t2};
                for (int side = 0; side < 2; ++side) {
                    for (int d = 0; d < ndim; ++d) {
                        for (int comp = 0; comp < 3; ++comp) {
                            double v = 0.0;
                            for (int a = 0; a < ndim; ++a) {
                                v += local[comp][side * ndim + a] * cp.input(axes[a] + d)[i];
                            }
                            cp.output(contact_col::jacobian + comp + 3 * (side * ndim + d))[i] = v;
                        }
                    }
                }
            } else {
                analytical_jacobian(cp, mp, opt, i);
            }
            cp.output(contact_col::status)[i] = st;
            cp.output(contact_col::subincrements)[i] = lanes_.col(subincrements)[i];
            cp.output(contact_col::newton_iterations)[i] = lanes_.col(newton)[i];
            cp.output(contact_col::evaluations)[i] = evals;
            cp.output(contact_col::model_substeps)[i] = lanes_.col(msub)[i];
            cp.output(contact_col::residual)[i] = lanes_.col(residual)[i];
            cp.output(contact_col::open)[i] = lanes_.col(open)[i];
            cp.output(contact_col::cause)[i] = why;
            cp.output(contact_col::band_clamped)[i] = lanes_.col(band_clamped)[i];
            cp.output(contact_col::dropped_columns)[i] = dropped;
            cp.output(contact_col::newton_fallbacks)[i] = fallbacks_all;
        }
    }

    // Eq. B3: J = M d eps / d g with only the first term of Eq. B2: the model's rate stiffness
    // at the new state, d eps_12 / d g_T1 = cos^2(dgamma) / (2 d_s) from Eq. 25; the normal
    // traction t_N = k_N g_N exactly; no coupling of tau with the normal gap.
    void analytical_jacobian(ContactPoints<M>& cp, const typename M::Params& mp,
                             const ContactOptions& opt, std::size_t i) {
        using namespace detail::lane_col;
        const int ndim = cp.ndim();
        StateVec<double, NS> y;
        for (int k = 0; k < NS; ++k) {
            y[k] = lanes_.col(state + k)[i];
        }
        const double eps_n = lanes_.col(state + NS + contact_state::eps_n)[i];
        const double d_s = band_thickness(opt.interface, eps_n);
        const double dgt[2] = {cp.input(contact_col::dg1)[i], cp.input(contact_col::dg2)[i]};
        const Sym<double> dir = {0.0, 0.0, 0.0, std::atan(dgt[0] / d_s), std::atan(dgt[1] / d_s),
                                 0.0};
        const auto cols = M::template rate_stiffness<double>(mp, opt.interface.model, y, dir);
        // An open lane's shear is the band's scaled by t_N / sigma_N (lane_traction).
        const bool open_lane = lanes_.col(open)[i] > 0.5;
        const double sigma_N = lanes_.col(state + 0)[i];
        const double fade = !open_lane ? 1.0
                            : sigma_N < 0.0
                                ? std::clamp(std::min(0.0, lanes_.col(t_N)[i]) / sigma_N, 0.0, 1.0)
                                : 0.0;
        double dtau[2][2];
        for (int a = 0; a < 2; ++a) {
            for (int b2 = 0; b2 < 2; ++b2) {
                const double cg = std::cos(dir[3 + b2]);
                dtau[a][b2] = fade * cols[3 + b2][3 + a] * 0.5 * cg * cg / d_s;
            }
        }
        const double k_N = cp.input(contact_col::k_N)[i]; // an open lane keeps the penalty
        double dtau_dgn[2] = {0.0, 0.0};
        if (open_lane && fade > 0.0 && lanes_.col(t_N)[i] < 0.0) {
            for (int a = 0; a < 2; ++a) {
                dtau_dgn[a] = lanes_.col(state + 3 + a)[i] / sigma_N * k_N;
            }
        }
        for (int side = 0; side < 2; ++side) {
            const double sgn = side == 0 ? 1.0 : -1.0; // gap change per +u: slave +, master -
            for (int d = 0; d < ndim; ++d) {
                const int c = side * ndim + d;
                const double n_d = cp.input(contact_col::n + d)[i];
                const double tt[2] = {cp.input(contact_col::t1 + d)[i],
                                      cp.input(contact_col::t2 + d)[i]};
                cp.output(contact_col::jacobian + 0 + 3 * c)[i] = k_N * sgn * n_d;
                for (int a = 0; a < 2; ++a) {
                    // dg_T,b = -(delta g . t_b); an open lane's shear tau_band t_N / sigma_N
                    // also follows t_N = k_N g_N.
                    cp.output(contact_col::jacobian + 1 + a + 3 * c)[i] =
                        -sgn * (dtau[a][0] * tt[0] + dtau[a][1] * tt[1]) + dtau_dgn[a] * sgn * n_d;
                }
            }
        }
    }

    ColumnStore lanes_;
    std::vector<detail::LaneKey> order_;          // base keys, then the lane queue; reused
    std::vector<unsigned char> reference_copied_; // per point: reference lane copied, not run
};

} // namespace ifsim
