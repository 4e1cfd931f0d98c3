#pragma once
// Valid, varied material states and strain increments for benchmarks and engine tests:
// K0-like stresses at several pressures with some shear, void ratios inside the admissible
// range, model state consistent with the stress, increments of a typical size in varied
// directions. Deterministic for a given seed.

#include <cmath>
#include <cstdint>
#include <random>

#include "engine/material_points.hpp"
#include "engine/model_registry.hpp"

namespace ifsim {

struct SampleSpec {
    std::uint64_t seed = 12345;
    double strain_increment = 1.0e-4; // norm of the increment per update
};

namespace detail {

inline void sample_common(std::mt19937_64& rng, Sym<double>& stress, double& e, double e_lo,
                          double e_hi) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const double p = 20.0 + 380.0 * u(rng);
    const double k0 = 0.45 + 0.5 * u(rng);
    const double s1 = -3.0 * p / (1.0 + 2.0 * k0);
    stress = {s1,
              k0 * s1,
              k0 * s1 * (0.9 + 0.2 * u(rng)),
              0.1 * s1 * (u(rng) - 0.5),
              0.05 * s1 * (u(rng) - 0.5),
              0.05 * s1 * (u(rng) - 0.5)};
    e = e_lo + (e_hi - e_lo) * u(rng);
}

inline Sym<double> sample_increment(std::mt19937_64& rng, double size) {
    std::normal_distribution<double> n(0.0, 1.0);
    Sym<double> d{n(rng), n(rng), n(rng), n(rng), n(rng), n(rng)};
    // Mostly compressive loading with some shear; never exactly zero.
    d[0] = -std::abs(d[0]) - 0.5;
    const double norm = voigt::norm(d);
    return voigt::scale(d, size / norm);
}

} // namespace detail

inline StateVec<double, Hypoplasticity::n_state> sample_state(const HypoplasticityParams& p,
                                                              std::mt19937_64& rng) {
    StateVec<double, Hypoplasticity::n_state> y{};
    Sym<double> s;
    double e;
    detail::sample_common(rng, s, e, p.e_d0 * 0.95, p.e_c0 * 0.95);
    set_stress(y, s);
    y[6] = e;
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Sym<double> h{u(rng), u(rng), u(rng), 0.5 * u(rng), 0.5 * u(rng), 0.5 * u(rng)};
    const double hn = voigt::norm(h);
    set_sym_at(y, Hypoplasticity::h_index, voigt::scale(h, p.R * 0.9 * std::abs(u(rng)) / hn));
    return y;
}

inline StateVec<double, Sanisand::n_state> sample_state(const SanisandParams& p,
                                                        std::mt19937_64& rng) {
    StateVec<double, Sanisand::n_state> y{};
    Sym<double> s;
    double e;
    detail::sample_common(rng, s, e, p.e0 - 0.45, p.e0 - 0.2);
    set_stress(y, s);
    y[6] = e;
    // Back-stress ratio on the cone axis: alpha = dev(sigma)/(tr(sigma)/3).
    const Sym<double> alpha = voigt::scale(voigt::deviator(s), 3.0 / voigt::trace(s));
    set_sym_at(y, 7, alpha);
    set_sym_at(y, 19, alpha);
    return y;
}

inline StateVec<double, LinearElastic::n_state> sample_state(const LinearElasticParams&,
                                                             std::mt19937_64& rng) {
    StateVec<double, LinearElastic::n_state> y{};
    Sym<double> s;
    double e;
    detail::sample_common(rng, s, e, 0.6, 0.8);
    set_stress(y, s);
    y[6] = e;
    return y;
}

// Fills every point of mp with a sampled state and increment.
template <class M>
void fill_samples(MaterialPoints<M>& mp, const typename M::Params& p, const SampleSpec& spec) {
    std::mt19937_64 rng(spec.seed);
    for (std::size_t i = 0; i < mp.size(); ++i) {
        mp.set_state(i, sample_state(p, rng));
        mp.set_deps(i, detail::sample_increment(rng, spec.strain_increment));
        mp.fixed_substeps()[i] = 0.0;
    }
}

} // namespace ifsim
