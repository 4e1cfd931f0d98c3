#pragma once
// One batched constitutive update over all points of a MaterialPoints set: trial state =
// committed state integrated over the point's strain increment. TBB runs fixed chunks of points
// on the worker threads; inside a chunk the SIMD path runs the kernel across lanes, the scalar
// path point by point. A point's result depends only on its own data, so the result is bitwise
// the same for any thread count; per-chunk sums are added in chunk order for the same reason.

#include <algorithm>
#include <cstddef>
#include <limits>
#include <vector>

#include "engine/material_points.hpp"
#include "engine/parallel_chunks.hpp"
#include "kernels/material_update.hpp"

namespace ifsim {

struct UpdateOptions {
    bool simd = true;               // false: the scalar reference path
    std::size_t chunk_points = 256; // points per TBB task (rounded up to the lane width)
    IntegrationSettings settings;
    double initial_substep = 1.0; // first substep as a fraction of the increment
};

struct UpdateReport {
    std::size_t points = 0;     // points updated (= constitutive evaluations)
    std::size_t failed = 0;     // points with status failed
    std::size_t unreliable = 0; // points where a safeguard acted
    std::size_t first_failed = std::numeric_limits<std::size_t>::max();
    double substeps = 0.0;
    double rejected = 0.0;
    double rate_evaluations = 0.0;
    bool ok() const { return failed == 0; }
};

namespace detail {

template <class M, class T>
void update_range(MaterialPoints<M>& mp, const typename M::Params& params, const UpdateOptions& opt,
                  std::size_t begin, std::size_t end) {
    constexpr int N = M::n_state;
    constexpr std::size_t W = simd::width_v<T>;
    for (std::size_t i = begin; i < end; i += W) {
        StateVec<T, N> y;
        Sym<T> de;
        SubstepControl<T> control;
        if constexpr (W == 1) {
            for (int k = 0; k < N; ++k) {
                y[k] = mp.committed(k)[i];
            }
            for (int j = 0; j < 6; ++j) {
                de[j] = mp.deps(j)[i];
            }
            control.fixed_substeps = mp.fixed_substeps()[i];
        } else {
            for (int k = 0; k < N; ++k) {
                y[k] = T::load_aligned(mp.committed(k) + i);
            }
            for (int j = 0; j < 6; ++j) {
                de[j] = T::load_aligned(mp.deps(j) + i);
            }
            control.fixed_substeps = T::load_aligned(mp.fixed_substeps() + i);
        }
        control.initial_substep = T(opt.initial_substep);
        UpdateStats<T> stats;
        material_update<M, T>(params, opt.settings, control, y, de, stats);
        if constexpr (W == 1) {
            for (int k = 0; k < N; ++k) {
                mp.trial(k)[i] = y[k];
            }
            mp.status()[i] = stats.status;
            mp.substeps()[i] = stats.substeps;
            mp.rejected()[i] = stats.rejected;
            mp.rate_evaluations()[i] = stats.rate_evaluations;
        } else {
            for (int k = 0; k < N; ++k) {
                y[k].store_aligned(mp.trial(k) + i);
            }
            stats.status.store_aligned(mp.status() + i);
            stats.substeps.store_aligned(mp.substeps() + i);
            stats.rejected.store_aligned(mp.rejected() + i);
            stats.rate_evaluations.store_aligned(mp.rate_evaluations() + i);
        }
    }
}

// One substep attempt: the model's own where it has a substep loop of its own (Sanisand), else
// integrate_explicit's. A model may also make its start state consistent before the first
// attempt (consistent_start); the refill runs that on the batch, so each lane's arithmetic is
// the same as in the model's integrate.
template <class M>
concept OwnSubstepLoop = requires {
    &M::template substep_attempt<double>;
};
template <class M>
concept HasConsistentStart = requires {
    &M::template consistent_start<double>;
};

template <class M, class T>
void attempt_substep(const typename M::Params& p, const IntegrationSettings& s,
                     const simd::mask_t<T>& fixed, StateVec<T, M::n_state>& y, T& t, T& dt,
                     const Sym<T>& deps, UpdateStats<T>& stats, const simd::mask_t<T>& active) {
    if constexpr (OwnSubstepLoop<M>) {
        M::template substep_attempt<T>(p, s, fixed, y, t, dt, deps, stats, active);
    } else {
        substep_attempt<M, T>(p, s, fixed, y, t, dt, deps, stats, active);
    }
}

// SIMD path with lane refill, for models integrated attempt by attempt: a lane whose point
// has finished its increment takes the next pending point at once, so a point that needs many
// substeps holds up only its own lane, not the whole batch. Each point's arithmetic is the same
// as in material_update(), so the result does not depend on which lane or when it ran.
template <class M>
void update_range_refill(MaterialPoints<M>& mp, const typename M::Params& params,
                         const UpdateOptions& opt, std::size_t begin, std::size_t end) {
    // A start made consistent belongs to the model's own loop; the generic attempt knows none.
    static_assert(!HasConsistentStart<M> || OwnSubstepLoop<M>);
    // substep_begin runs before consistent_start here (in load_lane), after it in Sanisand's
    // integrate: the same only because the first substep does not depend on the state.
    static_assert(!HasConsistentStart<M> || !CarriesSubstep<M>);
    constexpr int N = M::n_state;
    constexpr std::size_t W = simd::lanes;
    using B = simd::batch;
    const IntegrationSettings& s = opt.settings;
    alignas(64) double y[N][W], y0[N][W], de[6][W];
    alignas(64) double t[W], dt[W], fixed[W], st[W], sub[W], rej[W], rate[W], ideal[W];
    alignas(64) double fresh[W] = {}; // loaded since the last to_batches
    bool input_ok[W];
    std::size_t idx[W];
    bool busy[W];
    std::size_t next = begin;

    auto load_lane = [&](std::size_t l, std::size_t i) {
        StateVec<double, N> ys;
        for (int k = 0; k < N; ++k) {
            ys[k] = mp.committed(k)[i];
            y0[k][l] = ys[k];
        }
        Sym<double> d;
        for (int j = 0; j < 6; ++j) {
            d[j] = mp.deps(j)[i];
        }
        UpdateStats<double> stats;
        bool ok = true;
        const Sym<double> dd = material_prepare<M, double>(s, ys, d, stats, ok);
        for (int k = 0; k < N; ++k) {
            y[k][l] = ys[k];
        }
        for (int j = 0; j < 6; ++j) {
            de[j][l] = dd[j];
        }
        const SubstepControl<double> c{mp.fixed_substeps()[i], opt.initial_substep};
        substep_begin<M, double>(s, c, ys, dd, t[l], dt[l]);
        fresh[l] = 1.0;
        fixed[l] = c.fixed_substeps;
        st[l] = stats.status;
        sub[l] = rej[l] = rate[l] = ideal[l] = 0.0;
        input_ok[l] = ok;
        idx[l] = i;
        busy[l] = true;
    };
    auto idle_lane = [&](std::size_t l) {
        busy[l] = false;
        t[l] = 1.0; // inactive
        dt[l] = 1.0;
        for (int k = 0; k < N; ++k) {
            y[k][l] = k < 3 ? -100.0 : (k == 6 ? 0.7 : 0.0);
        }
        for (int j = 0; j < 6; ++j) {
            de[j][l] = 0.0;
        }
    };
    auto finish_lane = [&](std::size_t l) {
        StateVec<double, N> ys, ys0;
        for (int k = 0; k < N; ++k) {
            ys[k] = y[k][l];
            ys0[k] = y0[k][l];
        }
        UpdateStats<double> stats{st[l], sub[l], rej[l], rate[l], ideal[l]};
        if ((1.0 - t[l]) > 1.0e-12) { // ran out of substeps
            stats.status = lane_status::failed;
        }
        Sym<double> d;
        for (int j = 0; j < 6; ++j) {
            d[j] = de[j][l];
        }
        carry_substep<M, double>(ys, d, stats.ideal_substep, fixed[l] > 0.5);
        material_finish<M, double>(ys0, ys, input_ok[l], stats);
        const std::size_t i = idx[l];
        for (int k = 0; k < N; ++k) {
            mp.trial(k)[i] = ys[k];
        }
        mp.status()[i] = stats.status;
        mp.substeps()[i] = stats.substeps;
        mp.rejected()[i] = stats.rejected;
        mp.rate_evaluations()[i] = stats.rate_evaluations;
    };

    for (std::size_t l = 0; l < W; ++l) {
        if (next < end) {
            load_lane(l, next++);
        } else {
            idle_lane(l);
        }
    }
    // The lanes live in batches across attempts; they go through the arrays above only when a
    // lane finishes and is refilled.
    StateVec<B, N> yb;
    Sym<B> deb;
    B tb, dtb;
    simd::batch_mask fixedb;
    UpdateStats<B> stats;
    auto to_batches = [&] {
        for (int k = 0; k < N; ++k) {
            yb[k] = B::load_aligned(y[k]);
        }
        for (int j = 0; j < 6; ++j) {
            deb[j] = B::load_aligned(de[j]);
        }
        tb = B::load_aligned(t);
        dtb = B::load_aligned(dt);
        fixedb = B::load_aligned(fixed) > 0.5;
        stats = UpdateStats<B>{B::load_aligned(st), B::load_aligned(sub), B::load_aligned(rej),
                               B::load_aligned(rate), B::load_aligned(ideal)};
        if constexpr (HasConsistentStart<M>) {
            const simd::batch_mask start = B::load_aligned(fresh) > 0.5;
            if (simd::any(start)) {
                StateVec<B, N> consistent = yb;
                M::template consistent_start<B>(params, s, consistent);
                yb = select_state<B, N>(start, consistent, yb);
            }
        }
        std::fill(fresh, fresh + W, 0.0);
    };
    auto to_arrays = [&] {
        for (int k = 0; k < N; ++k) {
            yb[k].store_aligned(y[k]);
        }
        tb.store_aligned(t);
        dtb.store_aligned(dt);
        stats.status.store_aligned(st);
        stats.substeps.store_aligned(sub);
        stats.rejected.store_aligned(rej);
        stats.rate_evaluations.store_aligned(rate);
        stats.ideal_substep.store_aligned(ideal);
    };
    to_batches();
    alignas(64) double attempts_d[W] = {};
    B attempts_b = B::load_aligned(attempts_d);
    for (;;) {
        const simd::batch_mask active = (B(1.0) - tb) > 1.0e-12;
        if (simd::none(active)) {
            break; // every lane idle: no point pending
        }
        attempt_substep<M, B>(params, s, fixedb, yb, tb, dtb, deb, stats, active);
        attempts_b = attempts_b + simd::select(active, B(1.0), B(0.0));
        const simd::batch_mask finished =
            active && (((B(1.0) - tb) <= 1.0e-12) || (attempts_b >= double(s.max_substeps)));
        if (simd::none(finished)) {
            continue;
        }
        to_arrays();
        attempts_b.store_aligned(attempts_d);
        for (std::size_t l = 0; l < W; ++l) {
            if (!busy[l]) {
                continue;
            }
            if ((1.0 - t[l]) <= 1.0e-12 || attempts_d[l] >= s.max_substeps) {
                finish_lane(l);
                attempts_d[l] = 0.0;
                if (next < end) {
                    load_lane(l, next++);
                } else {
                    idle_lane(l);
                }
            }
        }
        to_batches();
        attempts_b = B::load_aligned(attempts_d);
    }
}

} // namespace detail

// Integrates every point; never throws on a bad point (see UpdateReport::failed).
template <class M>
UpdateReport batched_update(MaterialPoints<M>& mp, const typename M::Params& params,
                            const UpdateOptions& opt) {
    const std::size_t P = mp.padded();
    const std::size_t lanes = simd::lanes;
    const std::size_t chunk = ((opt.chunk_points + lanes - 1) / lanes) * lanes;
    for_chunks(P, chunk, [&](std::size_t b, std::size_t e) {
        if (opt.simd) {
            if constexpr (M::lane_refill) {
                detail::update_range_refill<M>(mp, params, opt, b, e);
            } else {
                detail::update_range<M, simd::batch>(mp, params, opt, b, e);
            }
        } else {
            detail::update_range<M, double>(mp, params, opt, b, e);
        }
    });

    // Serial reduction in point order: deterministic for any thread count.
    UpdateReport rep;
    rep.points = mp.size();
    for (std::size_t i = 0; i < mp.size(); ++i) {
        const double st = mp.status()[i];
        if (st < -0.5) {
            ++rep.failed;
            if (i < rep.first_failed) {
                rep.first_failed = i;
            }
        } else if (st < 0.5) {
            ++rep.unreliable;
        }
        rep.substeps += mp.substeps()[i];
        rep.rejected += mp.rejected()[i];
        rep.rate_evaluations += mp.rate_evaluations()[i];
    }
    return rep;
}

} // namespace ifsim
