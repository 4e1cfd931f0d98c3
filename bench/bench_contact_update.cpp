// Contact engine throughput: contact points updated per second, each update being the full
// Algorithm 1 for the base evaluation and its Eq. 37 Jacobian columns (3D: 7 lanes per point,
// 8 with adaptive sub-increments, whose perturbed lanes get a uniform re-run of the base as
// their reference). Batch sizes 1 .. 4096, scalar against SIMD path, 1 against 2 threads,
// fixed (paper: 5e-6) against adaptive sub-increments; hypoplasticity with the novel and the
// Stutz formulation, Sanisand with the novel one.
//
// States: engine/sample_states.hpp, rotated about the normal so that the in-plane shear
// sigma_23 vanishes (Eq. 17); t_N = sigma_11 and s_p1, s_p2 = sigma_22, sigma_33 (the continuum
// stress the interface is in equilibrium with), random local frames, tangential gap increments
// of 2-4 micrometres in a random in-plane direction. Before timing the points take one update
// and commit it (so adaptive points start from a sub-increment size they have used); inside
// the timing loop nothing is committed, so every iteration does the same work.
// Counter: points_per_s; the ratios at the end come from the same process run.
//
//   build/bench/bench_contact_update --benchmark_filter=Hypo-novel-fixed
#include <array>
#include <cmath>
#include <numbers>
#include <random>

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include "engine/contact_update.hpp"
#include "engine/sample_states.hpp"
#include "kernels/parameter_sets.hpp"
#include "ratio_reporter.hpp"

using namespace ifsim;

namespace {

template <class M>
typename M::Params bench_params();
template <>
HypoplasticityParams bench_params<Hypoplasticity>() {
    auto p = parameter_sets::hypoplasticity_l4c(); // paper §5, kappa = 0.9
    p.roughness = 0.9;
    p.prepare();
    return p;
}
template <>
SanisandParams bench_params<Sanisand>() {
    auto p = parameter_sets::sanisand_karlsruhe(); // paper §6
    p.prepare();
    return p;
}

using Mat3 = std::array<std::array<double, 3>, 3>;

Mat3 to_matrix(const Sym<double>& s) {
    return {{{s[0], s[3], s[4]}, {s[3], s[1], s[5]}, {s[4], s[5], s[2]}}};
}

Sym<double> to_voigt(const Mat3& a) {
    return {a[0][0], a[1][1], a[2][2], a[0][1], a[0][2], a[1][2]};
}

// Q A Q^T
Mat3 rotate(const Mat3& q, const Mat3& a) {
    Mat3 out{};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            double v = 0.0;
            for (int k = 0; k < 3; ++k) {
                for (int l = 0; l < 3; ++l) {
                    v += q[i][k] * a[k][l] * q[j][l];
                }
            }
            out[i][j] = v;
        }
    }
    return out;
}

// A sampled continuum state turned into an interface state: rotated about axis 1 (the normal)
// so that sigma_23 = 0. Every symmetric tensor of the state (stress, and the 6-blocks after the
// void ratio: h; alpha, z, alpha_in) turns with it, so the state stays consistent; a trailing
// scalar (the carried substep size) stays.
template <int NS>
StateVec<double, NS> to_interface_state(StateVec<double, NS> y) {
    const Sym<double> s = stress_of(y);
    const double angle = 0.5 * std::atan2(2.0 * s[5], s[1] - s[2]);
    const double c = std::cos(angle), sn = std::sin(angle);
    const Mat3 q = {{{1.0, 0.0, 0.0}, {0.0, c, sn}, {0.0, -sn, c}}};
    set_stress(y, to_voigt(rotate(q, to_matrix(s))));
    y[5] = 0.0; // exactly zero (round-off)
    static_assert((NS - 7) % 6 <= 1, "state: stress, void ratio, symmetric tensors, a scalar");
    for (int off = 7; off + 6 <= NS; off += 6) {
        set_sym_at(y, off, to_voigt(rotate(q, to_matrix(sym_at(y, off)))));
    }
    return y;
}

// A random right-handed orthonormal frame (n, t1, t2).
void random_frame(std::mt19937_64& rng, double n[3], double t1[3], double t2[3]) {
    std::normal_distribution<double> g(0.0, 1.0);
    auto normalise = [](double v[3]) {
        const double l = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        for (int d = 0; d < 3; ++d) {
            v[d] /= l;
        }
    };
    for (int d = 0; d < 3; ++d) {
        n[d] = g(rng);
        t1[d] = g(rng);
    }
    normalise(n);
    const double dot = n[0] * t1[0] + n[1] * t1[1] + n[2] * t1[2];
    for (int d = 0; d < 3; ++d) {
        t1[d] -= dot * n[d];
    }
    normalise(t1);
    t2[0] = n[1] * t1[2] - n[2] * t1[1];
    t2[1] = n[2] * t1[0] - n[0] * t1[2];
    t2[2] = n[0] * t1[1] - n[1] * t1[0];
}

template <class M>
void fill_contact_points(ContactPoints<M>& cp, const typename M::Params& p, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (std::size_t i = 0; i < cp.size(); ++i) {
        const auto y = to_interface_state<M::n_state>(sample_state(p, rng));
        cp.set_state(i, y);
        double n[3], t1[3], t2[3];
        random_frame(rng, n, t1, t2);
        cp.set_frame(i, n, t1, t2);
        const double dg = (2.0 + 2.0 * u(rng)) * 1.0e-6; // 2-4 micrometres
        const double dir = 2.0 * std::numbers::pi * u(rng);
        cp.input(contact_col::t_N)[i] = y[0];
        cp.input(contact_col::k_N)[i] = 1.0e6; // kPa/m, a penalty
        cp.input(contact_col::dg1)[i] = dg * std::cos(dir);
        cp.input(contact_col::dg2)[i] = dg * std::sin(dir);
        cp.input(contact_col::s_p1)[i] = y[1];
        cp.input(contact_col::s_p2)[i] = y[2];
    }
}

template <class M>
void BM_contact(benchmark::State& state, InterfaceFormulation formulation, bool adaptive) {
    const auto points = static_cast<std::size_t>(state.range(0));
    const bool use_simd = state.range(1) != 0;
    const int threads = static_cast<int>(state.range(2));
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    const auto params = bench_params<M>();
    ContactPoints<M> cp(points, 3);
    fill_contact_points(cp, params, 20220101);
    ContactOptions opt;
    opt.simd = use_simd;
    opt.interface.formulation = formulation;
    opt.interface.ndim = 3;
    opt.interface.adaptive = adaptive;
    ContactEngine<M> engine;
    engine.update(cp, params, opt); // warm-up: buffers, and one committed increment
    cp.commit();

    ContactReport rep;
    double evaluations = 0.0, subincrements = 0.0, lanes = 0.0;
    std::size_t failed = 0;
    for (auto _ : state) {
        rep = engine.update(cp, params, opt);
        evaluations += rep.constitutive_evaluations;
        subincrements += rep.subincrements;
        lanes += rep.lanes;
        failed += rep.failed;
        benchmark::DoNotOptimize(cp.output(contact_col::traction));
    }
    const double updates = static_cast<double>(points) * static_cast<double>(state.iterations());
    state.counters["points_per_s"] = benchmark::Counter(updates, benchmark::Counter::kIsRate);
    state.counters["lanes_per_pt"] = lanes / updates;
    state.counters["evals_per_pt"] = evaluations / updates;
    state.counters["subinc_per_pt"] = subincrements / updates;
    state.counters["failed_frac"] = static_cast<double>(failed) / updates;
}

void sizes(benchmark::internal::Benchmark* b) {
    b->ArgNames({"points", "simd", "threads"});
    for (long n : {1L, 8L, 64L, 512L, 4096L}) {
        for (long simd : {0L, 1L}) {
            for (long threads : {1L, 2L}) {
                b->Args({n, simd, threads});
            }
        }
    }
    b->UseRealTime();
    b->Unit(benchmark::kMillisecond);
}

} // namespace

int main(int argc, char** argv) {
    struct Family {
        const char* name;
        void (*fn)(benchmark::State&, InterfaceFormulation, bool);
        InterfaceFormulation formulation;
        bool adaptive;
    };
    const Family families[] = {
        {"Hypo-novel-fixed", BM_contact<Hypoplasticity>, InterfaceFormulation::novel, false},
        {"Hypo-novel-adaptive", BM_contact<Hypoplasticity>, InterfaceFormulation::novel, true},
        {"Hypo-stutz-fixed", BM_contact<Hypoplasticity>, InterfaceFormulation::stutz, false},
        {"Hypo-stutz-adaptive", BM_contact<Hypoplasticity>, InterfaceFormulation::stutz, true},
        {"Sanisand-novel-fixed", BM_contact<Sanisand>, InterfaceFormulation::novel, false},
        {"Sanisand-novel-adaptive", BM_contact<Sanisand>, InterfaceFormulation::novel, true},
    };
    for (const Family& f : families) {
        benchmark::RegisterBenchmark(f.name, f.fn, f.formulation, f.adaptive)->Apply(sizes);
    }
    benchmark::Initialize(&argc, argv);
    ifsim::bench::RatioReporter reporter("points_per_s");
    benchmark::RunSpecifiedBenchmarks(&reporter);
    benchmark::Shutdown();
    return 0;
}
