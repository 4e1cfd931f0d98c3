#pragma once
// The engine's one way to spread work over TBB threads: fixed chunks (simple_partitioner), so
// the split of the work never depends on the thread count, and every point or element writes
// only its own data: results are bitwise independent of the number of threads.

#include <cstddef>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

namespace ifsim {

// body(begin, end) for the chunks [k chunk, min((k + 1) chunk, n)) of [0, n), one TBB task per
// chunk. Chunks start at multiples of `chunk` (a multiple of the SIMD width keeps batches
// aligned).
template <class F>
void for_chunks(std::size_t n, std::size_t chunk, F&& body) {
    const std::size_t size = chunk > 0 ? chunk : 1;
    const std::size_t n_chunks = (n + size - 1) / size;
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, n_chunks, 1),
        [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t c = r.begin(); c != r.end(); ++c) {
                const std::size_t b = c * size;
                body(b, b + size < n ? b + size : n);
            }
        },
        tbb::simple_partitioner());
}

// body(i) for every i in [0, n), in tasks of at most `grain` indices.
template <class F>
void for_each_index(std::size_t n, std::size_t grain, F&& body) {
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, n, grain > 0 ? grain : 1),
        [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) {
                body(i);
            }
        },
        tbb::simple_partitioner());
}

} // namespace ifsim
