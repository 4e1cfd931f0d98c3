// The finite-element shear box with the hypoplastic interface (novel formulation, Eq. 37
// Jacobian) as a benchmark of the whole FE step: iterations per increment for each Jacobian
// scheme, the time split by phase (paper Table 5), and 1 against 2 threads on a box with many
// contact points. Reports counters per run: Newton iterations per increment and seconds per
// phase. Run: build/bench/bench_fe_shear_box (see docs/performance.md).
#include <benchmark/benchmark.h>

#define IFSIM_TEST_ENGINE_HELPERS
#include "tests/fem/fe_shear_box.hpp"

namespace {

using namespace ifsim;
using namespace ifsim::fem;
using namespace ifsim::fem::testing;

void report(benchmark::State& state, const ShearBoxRun& r, int increments) {
    if (!r.ok) {
        state.SkipWithError(r.reason.c_str());
        return;
    }
    state.counters["iterations_per_increment"] =
        static_cast<double>(r.counters.newton_iterations) / (increments + 1);
    state.counters["contact_lanes"] = r.counters.contact_lanes;
    state.counters["element_s"] = r.timers.element;
    state.counters["assembly_s"] = r.timers.assembly;
    state.counters["solve_s"] = r.timers.solve;
    state.counters["search_s"] = r.timers.contact_search;
    state.counters["gather_s"] = r.timers.contact_gather;
    state.counters["kernels_s"] = r.timers.contact_kernels;
    state.counters["scatter_s"] = r.timers.contact_scatter;
}

// Args: dimension, soil elements per horizontal axis, threads, Jacobian (0 Eq. 37, 2 B3),
// Jacobian lanes deferred to the tangent pass (1) or run with every residual (0), increments
// of 50 micrometres.
void BM_FeShearBox(benchmark::State& state) {
    ShearBoxOptions o;
    o.dim = static_cast<int>(state.range(0));
    o.soil_elements = static_cast<int>(state.range(1));
    o.plate_elements = o.soil_elements + 4;
    o.threads = static_cast<int>(state.range(2));
    o.jacobian = static_cast<ContactJacobian>(state.range(3));
    o.steps = static_cast<int>(state.range(5));
    o.displacement = 5.0e-5 * o.steps;
    o.max_iterations = 500; // B3 converges linearly
    const bool defer = state.range(4) != 0;
    o.adjust = [defer](ContactPairSpec& c) { c.defer_jacobian = defer; };
    ShearBoxRun r;
    for (auto _ : state) {
        r = run_shear_box(o);
    }
    report(state, r, o.steps);
}

} // namespace

// The §5 box (one soil element) in 2D and 3D with both Jacobian schemes.
BENCHMARK(BM_FeShearBox)
    ->ArgNames({"dim", "soil", "threads", "jacobian", "defer", "steps"})
    ->Args({2, 1, 1, 0, 1, 10})
    ->Args({2, 1, 1, 2, 1, 10})
    ->Args({3, 1, 1, 0, 1, 10})
    ->Args({3, 1, 1, 2, 1, 10})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);
// A box with 12 x 12 soil elements (576 contact points): thread scaling.
BENCHMARK(BM_FeShearBox)
    ->ArgNames({"dim", "soil", "threads", "jacobian", "defer", "steps"})
    ->Args({3, 12, 1, 0, 1, 10})
    ->Args({3, 12, 2, 0, 1, 10})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->UseRealTime();

// Deferred against eager Jacobian lanes on a long run (the scenes' regime: 1-2 iterations per
// increment once the extrapolated increment is right).
BENCHMARK(BM_FeShearBox)
    ->ArgNames({"dim", "soil", "threads", "jacobian", "defer", "steps"})
    ->Args({2, 1, 1, 0, 0, 120})
    ->Args({2, 1, 1, 0, 1, 120})
    ->Args({3, 1, 1, 0, 0, 120})
    ->Args({3, 1, 1, 0, 1, 120})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

BENCHMARK_MAIN();
