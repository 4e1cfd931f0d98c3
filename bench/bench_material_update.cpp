// Batched constitutive update throughput per model: batch sizes 1 .. 1e5, scalar against SIMD
// path, 1 against 2 threads. The same sampled states are updated every iteration (no commit),
// so every iteration does the same work. Counter: evals_per_s = point updates per second.
//
//   build/bench/bench_material_update --benchmark_filter=Hypoplasticity
//   build/bench/bench_material_update --benchmark_filter=SanisandPaths   (path 0 scalar, 1 SIMD
//   batch by batch, 2 SIMD with lane refill)
#include <benchmark/benchmark.h>

#include <cmath>

#include <tbb/global_control.h>

#include "engine/batched_update.hpp"
#include "engine/sample_states.hpp"
#include "kernels/parameter_sets.hpp"
#include "ratio_reporter.hpp"

using namespace ifsim;

namespace {

template <class M>
typename M::Params bench_params();
template <>
HypoplasticityParams bench_params<Hypoplasticity>() {
    auto p = parameter_sets::hypoplasticity_karlsruhe();
    p.prepare();
    return p;
}
template <>
SanisandParams bench_params<Sanisand>() {
    auto p = *parameter_sets::sanisand("karlsruhe-sand");
    p.prepare();
    return p;
}
template <>
LinearElasticParams bench_params<LinearElastic>() {
    return LinearElasticParams{};
}

// identical = true: every point gets the first sampled state and increment, so all lanes take
// the same substeps (shows what lane divergence costs the SIMD path).
template <class M, bool identical = false>
void BM_update(benchmark::State& state) {
    const auto points = static_cast<std::size_t>(state.range(0));
    const bool use_simd = state.range(1) != 0;
    const int threads = static_cast<int>(state.range(2));
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    const auto params = bench_params<M>();
    MaterialPoints<M> mp(points);
    fill_samples(mp, params, SampleSpec{});
    if constexpr (identical) {
        const auto y = mp.state(0);
        Sym<double> d;
        for (int j = 0; j < 6; ++j) {
            d[j] = mp.deps(j)[0];
        }
        for (std::size_t i = 0; i < points; ++i) {
            mp.set_state(i, y);
            mp.set_deps(i, d);
        }
    }
    UpdateOptions opt;
    opt.simd = use_simd;
    double substeps = 0.0;
    for (auto _ : state) {
        const UpdateReport rep = batched_update(mp, params, opt);
        substeps += rep.substeps;
        benchmark::DoNotOptimize(mp.trial(0));
    }
    const double evals = static_cast<double>(points) * static_cast<double>(state.iterations());
    state.counters["evals_per_s"] = benchmark::Counter(evals, benchmark::Counter::kIsRate);
    state.counters["substeps_per_eval"] = substeps / evals;
}

// Sanisand's three paths on the same points, one thread: path 0 scalar, 1 SIMD batch by batch
// (a batch runs until its slowest lane is done; what batched_update runs for Sanisand), 2 SIMD
// with lane refill (what batched_update runs for models with lane_refill; measured and not
// adopted for Sanisand, docs/performance.md). One range, no 256-point chunks. Increment norm
// 10^-exponent.
void BM_sanisand_paths(benchmark::State& state) {
    const auto points = static_cast<std::size_t>(state.range(0));
    const long path = state.range(1);
    const double increment = std::pow(10.0, -static_cast<double>(state.range(2)));
    const auto params = bench_params<Sanisand>();
    MaterialPoints<Sanisand> mp(points);
    fill_samples(mp, params, SampleSpec{12345, increment});
    UpdateOptions opt;
    opt.simd = path != 0;
    for (auto _ : state) {
        if (path == 1) {
            detail::update_range<Sanisand, simd::batch>(mp, params, opt, 0, mp.padded());
        } else if (path == 2) {
            detail::update_range_refill<Sanisand>(mp, params, opt, 0, mp.padded());
        } else {
            detail::update_range<Sanisand, double>(mp, params, opt, 0, mp.padded());
        }
        benchmark::DoNotOptimize(mp.trial(0));
    }
    const double evals = static_cast<double>(points) * static_cast<double>(state.iterations());
    state.counters["evals_per_s"] = benchmark::Counter(evals, benchmark::Counter::kIsRate);
}

void sizes(benchmark::internal::Benchmark* b) {
    b->ArgNames({"points", "simd", "threads"});
    for (long n : {1L, 10L, 100L, 1000L, 10000L, 100000L}) {
        for (long simd : {0L, 1L}) {
            for (long threads : {1L, 2L}) {
                b->Args({n, simd, threads});
            }
        }
    }
    b->UseRealTime();
}

BENCHMARK(BM_update<Hypoplasticity>)->Name("Hypoplasticity")->Apply(sizes);
BENCHMARK(BM_update<Hypoplasticity, true>)->Name("HypoplasticityIdenticalStates")->Apply(sizes);
BENCHMARK(BM_update<Sanisand>)->Name("Sanisand")->Apply(sizes);
BENCHMARK(BM_update<LinearElastic>)->Name("LinearElastic")->Apply(sizes);
BENCHMARK(BM_sanisand_paths)
    ->Name("SanisandPaths")
    ->ArgNames({"points", "path", "increment_exp"})
    ->ArgsProduct({{4096}, {0, 1, 2}, {3, 4, 5}})
    ->UseRealTime();

} // namespace

int main(int argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    ifsim::bench::RatioReporter reporter("evals_per_s");
    benchmark::RunSpecifiedBenchmarks(&reporter);
    benchmark::Shutdown();
    return 0;
}
