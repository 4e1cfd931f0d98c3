#pragma once
// Shared set-up of the fem tests: materials, initial states, and helpers that prescribe a
// displacement field node by node (one node set per node).

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "fem/static_solver.hpp"
#include "fem/structured_mesh.hpp"
#include "kernels/parameter_sets.hpp"

namespace ifsim::fem::testing {

inline std::vector<double> elastic_state(double p = 0.0) {
    return {-p, -p, -p, 0.0, 0.0, 0.0, 0.7};
}

inline HypoplasticityParams karlsruhe() {
    auto p = parameter_sets::hypoplasticity_karlsruhe();
    p.prepare();
    return p;
}

// Hypoplastic state: given stress, void ratio, zero intergranular strain.
inline std::vector<double> hypo_state(const Sym<double>& stress, double e) {
    std::vector<double> y(Hypoplasticity::n_state, 0.0);
    for (int i = 0; i < 6; ++i) {
        y[static_cast<std::size_t>(i)] = stress[static_cast<std::size_t>(i)];
    }
    y[6] = e;
    return y;
}

inline ElementSetMaterial material(MaterialChoice m, std::vector<double> y0,
                                   const std::string& set = "all") {
    ElementSetMaterial s;
    s.element_set = set;
    s.material = std::move(m);
    s.initial_state = std::move(y0);
    return s;
}

// Moves every node by up to `amount` times the element size in each direction (seeded).
inline void distort(Mesh& m, double amount, double h, unsigned seed = 7) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-amount * h, amount * h);
    for (double& x : m.coordinates) {
        x += u(rng);
    }
}

// One stage run on a hypoplastic block: its result, the solver's counters, and the committed
// stress of the first element's first integration point.
struct StageRun {
    StageResult result;
    SolverCounters counters;
    std::vector<double> stress;
};

// Runs `stage` on `m` (one hypoplastic material, Karlsruhe sand, start state y0) with `s`.
inline StageRun run_hypoplastic_stage(const Mesh& m, std::vector<double> y0,
                                      const SolverSettings& s, const Stage& stage) {
    StaticSolver solver(m, {material(karlsruhe(), std::move(y0))}, s);
    StageRun out;
    out.result = solver.run_stage(stage);
    out.counters = solver.counters();
    const auto y = solver.state(0, 0);
    out.stress.assign(y.begin(), y.begin() + 6);
    return out;
}

// Node set "n<id>" for a single node.
inline std::string single_node_set(Mesh& m, int node) {
    const std::string name = fmt::format("n{}", node); // (GCC 12 -Wrestrict on "n" + string)
    m.node_sets[name] = {node};
    return name;
}

// Linear elastic stress of a strain (tensor components).
inline Sym<double> hooke(double E, double nu, const Sym<double>& eps) {
    const double G = E / (2.0 * (1.0 + nu));
    const double lambda = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
    const double tr = eps[0] + eps[1] + eps[2];
    Sym<double> s;
    for (int i = 0; i < 6; ++i) {
        s[static_cast<std::size_t>(i)] =
            2.0 * G * eps[static_cast<std::size_t>(i)] + (i < 3 ? lambda * tr : 0.0);
    }
    return s;
}

inline double max_abs(const std::vector<double>& v) {
    double m = 0.0;
    for (double x : v) {
        m = std::max(m, std::abs(x));
    }
    return m;
}

} // namespace ifsim::fem::testing
