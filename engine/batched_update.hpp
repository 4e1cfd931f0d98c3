#pragma once
// One batched constitutive update over all points of a MaterialPoints set: trial state =
// committed state integrated over the point's strain increment. TBB runs fixed chunks of points
// on the worker threads; inside a chunk the SIMD path runs the kernel across lanes, the scalar
// path point by point. A point's result depends only on its own data, so the result is bitwise
// the same for any thread count; per-chunk sums are added in chunk order for the same reason.

#include <cstddef>
#include <limits>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include "engine/material_points.hpp"
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

} // namespace detail

// Integrates every point; never throws on a bad point (see UpdateReport::failed).
template <class M>
UpdateReport batched_update(MaterialPoints<M>& mp, const typename M::Params& params,
                            const UpdateOptions& opt) {
    const std::size_t P = mp.padded();
    const std::size_t lanes = simd::lanes;
    const std::size_t chunk = ((opt.chunk_points + lanes - 1) / lanes) * lanes;
    const std::size_t n_chunks = (P + chunk - 1) / chunk;
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, n_chunks, 1),
        [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t c = r.begin(); c != r.end(); ++c) {
                const std::size_t b = c * chunk;
                const std::size_t e = b + chunk < P ? b + chunk : P;
                if (opt.simd) {
                    detail::update_range<M, simd::batch>(mp, params, opt, b, e);
                } else {
                    detail::update_range<M, double>(mp, params, opt, b, e);
                }
            }
        },
        tbb::simple_partitioner());

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
