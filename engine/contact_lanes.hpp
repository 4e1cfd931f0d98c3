#pragma once
// The lanes of the contact engine's lane buffer run through Algorithm 1.
//
// Scalar path: lane by lane. SIMD path: the lanes of a task are ordered by the number of
// sub-increments they are expected to take (estimate_work, sort_by_work) and packed into
// batches in that order, so the lanes of a batch finish together and go through their costly
// first sub-increments together. Kept in buffer order, a batch of 8 lanes used only ~70% of its
// sub-increment iterations (the count follows |delta g_T|, and a batch waits for its slowest
// lane); refilling a slot as soon as its lane finished fixed that but put lanes at different
// stages side by side, and the model's substeps per evaluation (many more in the first
// sub-increments, or in the large adaptive ones) then cost the batch more than it gained
// (measured, docs/performance.md). A lane's arithmetic depends only on its own data
// (interface_begin/step/end), so the result does not depend on the slot, the neighbours or the
// order of the lanes.

#include <algorithm>
#include <cstddef>
#include <type_traits>

#include "engine/column_store.hpp"
#include "engine/contact_points.hpp"
#include "kernels/interface_algorithm1.hpp"

namespace ifsim::detail {

// Lane buffer columns: inputs, state, results.
namespace lane_col {
inline constexpr int t_N = 0, dg1 = 1, dg2 = 2, s_p1 = 3, s_p2 = 4, forced = 5;
inline constexpr int status = 6, subincrements = 7, newton = 8, evaluations = 9, msub = 10,
                     residual = 11, open = 12, cause = 13, band_clamped = 14, fallbacks = 15;
inline constexpr int state = 16; // then NS + 6 state columns
} // namespace lane_col

// A lane of the buffer and the work it is expected to take (sub-increments).
struct LaneKey {
    double work = 0.0;
    std::size_t lane = 0;
};

// The pending lanes of one run, taken in order.
struct LaneQueue {
    const LaneKey* keys;
    std::size_t n;
    std::size_t next = 0;

    bool pop(std::size_t& lane) {
        if (next == n) {
            return false;
        }
        lane = keys[next++].lane;
        return true;
    }
};

template <class M>
InterfaceState<double, M::n_state> read_lane_state(const ColumnStore& lanes, std::size_t l) {
    using namespace lane_col;
    constexpr int NS = M::n_state;
    InterfaceState<double, NS> st;
    for (int k = 0; k < NS; ++k) {
        st.y[k] = lanes.col(state + k)[l];
    }
    st.eps_n = lanes.col(state + NS + contact_state::eps_n)[l];
    st.eps_p1 = lanes.col(state + NS + contact_state::eps_p1)[l];
    st.eps_p2 = lanes.col(state + NS + contact_state::eps_p2)[l];
    st.gamma1 = lanes.col(state + NS + contact_state::gamma1)[l];
    st.gamma2 = lanes.col(state + NS + contact_state::gamma2)[l];
    st.last_subincrement = lanes.col(state + NS + contact_state::last_sub)[l];
    return st;
}

inline InterfaceInput<double> read_lane_input(const ColumnStore& lanes, std::size_t l) {
    using namespace lane_col;
    return {lanes.col(t_N)[l],  lanes.col(dg1)[l],  lanes.col(dg2)[l],
            lanes.col(s_p1)[l], lanes.col(s_p2)[l], lanes.col(forced)[l]};
}

template <class M>
void write_lane(ColumnStore& lanes, std::size_t l, const InterfaceState<double, M::n_state>& st,
                const InterfaceStats<double>& stats) {
    using namespace lane_col;
    constexpr int NS = M::n_state;
    for (int k = 0; k < NS; ++k) {
        lanes.col(state + k)[l] = st.y[k];
    }
    lanes.col(state + NS + contact_state::eps_n)[l] = st.eps_n;
    lanes.col(state + NS + contact_state::eps_p1)[l] = st.eps_p1;
    lanes.col(state + NS + contact_state::eps_p2)[l] = st.eps_p2;
    lanes.col(state + NS + contact_state::gamma1)[l] = st.gamma1;
    lanes.col(state + NS + contact_state::gamma2)[l] = st.gamma2;
    lanes.col(state + NS + contact_state::last_sub)[l] = st.last_subincrement;
    lanes.col(status)[l] = stats.status;
    lanes.col(subincrements)[l] = stats.subincrements;
    lanes.col(newton)[l] = stats.newton_iterations;
    lanes.col(evaluations)[l] = stats.evaluations;
    lanes.col(msub)[l] = stats.model_substeps;
    lanes.col(residual)[l] = stats.residual;
    lanes.col(open)[l] = stats.open;
    lanes.col(cause)[l] = stats.cause;
    lanes.col(band_clamped)[l] = stats.band_clamped;
    lanes.col(fallbacks)[l] = stats.newton_fallbacks;
}

// Scalar reference path.
template <class M>
void run_lanes_scalar(const typename M::Params& mp, const InterfaceSettings& s, ColumnStore& lanes,
                      LaneQueue q) {
    std::size_t l = 0;
    while (q.pop(l)) {
        auto st = read_lane_state<M>(lanes, l);
        InterfaceStats<double> stats;
        interface_update<M, double>(mp, s, st, read_lane_input(lanes, l), stats);
        write_lane<M>(lanes, l, st, stats);
    }
}

// Each lane's expected number of sub-increments (fixed and forced: exact; adaptive: from the
// first sub-increment size) into its key.
template <class M>
void estimate_work(const InterfaceSettings& s, const ColumnStore& lanes, LaneKey* keys,
                   std::size_t n) {
    for (std::size_t q = 0; q < n; ++q) {
        const std::size_t l = keys[q].lane;
        const auto c =
            interface_begin<M, double>(s, read_lane_state<M>(lanes, l), read_lane_input(lanes, l));
        keys[q].work = c.active ? 1.0 / c.h : 0.0;
    }
}

// Most work first; ties in buffer order. The order changes no result.
inline void sort_by_work(LaneKey* keys, std::size_t n) {
    std::sort(keys, keys + n, [](const LaneKey& a, const LaneKey& b) {
        return a.work != b.work ? a.work > b.work : a.lane < b.lane;
    });
}

// Moves one lane (slot j) between a batch carry and a scalar carry, field by field.
struct LaneSlot {
    std::size_t j;
    bool to_batch;
    void operator()(simd::batch& b, double& v) const {
        alignas(64) double buf[simd::lanes];
        b.store_aligned(buf);
        if (to_batch) {
            buf[j] = v;
            b = simd::batch::load_aligned(buf);
        } else {
            v = buf[j];
        }
    }
    void operator()(simd::batch_mask& b, bool& v) const {
        alignas(64) bool buf[simd::lanes];
        b.store_aligned(buf);
        if (to_batch) {
            buf[j] = v;
            b = simd::batch_mask::load_aligned(buf);
        } else {
            v = buf[j];
        }
    }
};

// SIMD path: the lanes, ordered by sort_by_work, run in batches of simd::lanes; a batch is
// loaded when all its lanes are done. Lanes without sub-increments to run do not take a slot.
template <class M>
void run_lanes_packed(const typename M::Params& mp, const InterfaceSettings& s, ColumnStore& lanes,
                      LaneQueue q) {
    constexpr int NS = M::n_state;
    constexpr std::size_t W = simd::lanes;
    using Lane = Algorithm1Lane<double, NS>;

    // A lane finishes: its start state is still in the buffer; the result replaces it.
    auto finish = [&](std::size_t l, const Lane& one) {
        auto st = read_lane_state<M>(lanes, l);
        InterfaceStats<double> stats;
        interface_end<M, double>(s, one, st, stats);
        write_lane<M>(lanes, l, st, stats);
    };
    // The next pending lane that has sub-increments to run; lanes that have none (open
    // contact, invalid input) are finished on the way.
    auto next_runnable = [&](Lane& one, std::size_t& l) {
        while (q.pop(l)) {
            one = interface_begin<M, double>(s, read_lane_state<M>(lanes, l),
                                             read_lane_input(lanes, l));
            if (one.active) {
                return true;
            }
            finish(l, one);
        }
        return false;
    };

    Algorithm1Lane<simd::batch, NS> c;
    Lane one;
    std::size_t idx[W];
    alignas(64) bool used[W];
    for (;;) {
        std::size_t n = 0;
        while (n < W && next_runnable(one, idx[n])) {
            if (n == 0) {
                // Every slot a copy of the first lane: idle slots compute on valid numbers.
                zip_fields(c, one,
                           [](auto& b, auto& v) { b = std::remove_reference_t<decltype(b)>(v); });
            } else {
                zip_fields(c, one, LaneSlot{n, true});
            }
            ++n;
        }
        if (n == 0) {
            return;
        }
        for (std::size_t j = 0; j < W; ++j) {
            used[j] = j < n;
        }
        c.active = c.active && simd::batch_mask::load_aligned(used);
        while (simd::any(c.active)) {
            interface_step<M, simd::batch>(mp, s, c);
        }
        for (std::size_t j = 0; j < n; ++j) {
            zip_fields(c, one, LaneSlot{j, false});
            finish(idx[j], one);
        }
    }
}

} // namespace ifsim::detail
