#include "io/element_test/element_initial_state.hpp"

#include <algorithm>
#include <cmath>
#include <variant>

#include <fmt/format.h>

namespace ifsim::io {

namespace {

using Six = std::array<double, 6>;

double trace(const Six& a) {
    return a[0] + a[1] + a[2];
}

double norm(const Six& a) {
    // Tensor shear components: each counts twice in a : a.
    return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2] +
                     2.0 * (a[3] * a[3] + a[4] * a[4] + a[5] * a[5]));
}

// Mean pressure p = -tr(sigma)/3 > 0 for the granular models (compression negative).
double compressive_pressure(const TableReader& initial, const Six& stress) {
    const double p = -trace(stress) / 3.0;
    if (!(p > 0.0)) {
        initial.fail("stress", fmt::format("expected a compressive stress state (mean stress "
                                           "tr(sigma)/3 < 0 kPa, compression negative), got "
                                           "mean stress {} kPa",
                                           -p));
    }
    return p;
}

void append(std::vector<double>& y, const Six& a) {
    y.insert(y.end(), a.begin(), a.end());
}

void hypoplasticity_state(const TableReader& initial, const HypoplasticityParams& p,
                          const Six& stress, double e, std::vector<double>& y) {
    const double pressure = compressive_pressure(initial, stress);
    // Bauer's law: the limit void ratios at this pressure bound the admissible states.
    const double bauer = std::exp(-std::pow(3.0 * pressure / p.h_s, p.n));
    const double e_i = p.e_i0 * bauer;
    const double e_d = p.e_d0 * bauer;
    if (e > e_i || e < e_d) {
        initial.fail("void_ratio",
                     fmt::format("expected a void ratio between e_d = {:.4f} and e_i = {:.4f} "
                                 "(hypoplasticity's admissible range at p = {:.4g} kPa), got {}",
                                 e_d, e_i, pressure, e));
    }
    Six h{};
    if (initial.has("intergranular_strain")) {
        h = initial.six_numbers("intergranular_strain");
        if (norm(h) > p.R * (1.0 + 1.0e-6)) {
            initial.fail("intergranular_strain",
                         fmt::format("expected |h| <= R = {} (norm with the shear components "
                                     "counted twice), got |h| = {}",
                                     p.R, norm(h)));
        }
    }
    append(y, h);
    y.push_back(0.0); // no carried substep yet: the first update starts with the whole increment
}

// Largest |psi| = |e - e_c(p)| a Sanisand state may start with. The model has no void-ratio
// bounds of its own; Dafalias & Manzari (2004) calibrated Toyoura sand on states of psi from
// about -0.2 to +0.1, so +-0.5 already extrapolates far, and beyond it (e = 0.01 was accepted
// and ran on to 0.008) the numbers no longer describe any sand.
constexpr double sanisand_max_state_parameter = 0.5;

void sanisand_state(const TableReader& initial, const SanisandParams& p, const Six& stress,
                    double e, std::vector<double>& y) {
    const double pressure = compressive_pressure(initial, stress);
    const double e_c = p.e0 - p.lambda_c * std::pow(pressure / p.p_a, p.xi);
    if (!(std::abs(e - e_c) <= sanisand_max_state_parameter)) {
        initial.fail("void_ratio",
                     fmt::format("expected a void ratio within {} of the critical state line, "
                                 "e_c = {:.4f} at p = {:.4g} kPa (state parameter |psi| <= {}), "
                                 "got {} (psi = {:.3g})",
                                 sanisand_max_state_parameter, e_c, pressure,
                                 sanisand_max_state_parameter, e, e - e_c));
    }
    // Stress ratio r = dev(sigma)/(tr(sigma)/3): the same in both sign conventions.
    const double mean = trace(stress) / 3.0;
    Six r{};
    for (int i = 0; i < 6; ++i) {
        r[i] = (stress[i] - (i < 3 ? mean : 0.0)) / mean;
    }
    Six alpha = r;
    if (initial.has("back_stress")) {
        alpha = initial.six_numbers("back_stress");
        if (std::abs(trace(alpha)) > 1.0e-9 * std::max(1.0, norm(alpha))) {
            initial.fail("back_stress",
                         fmt::format("expected a deviatoric back-stress ratio (alpha11 + alpha22 "
                                     "+ alpha33 = 0), got trace {}",
                                     trace(alpha)));
        }
    }
    // Yield surface f = |r - alpha| - sqrt(2/3) m <= 0 (divided by p > 0).
    Six diff{};
    for (int i = 0; i < 6; ++i) {
        diff[i] = r[i] - alpha[i];
    }
    const double radius = std::sqrt(2.0 / 3.0) * p.m;
    if (norm(diff) > radius * (1.0 + 1.0e-9)) {
        initial.fail("back_stress",
                     fmt::format("the initial state lies outside the yield surface: |r - alpha| = "
                                 "{:.6g} > sqrt(2/3) m = {:.6g} with r = dev(sigma)/(tr(sigma)/3); "
                                 "expected a back_stress within the cone around the stress ratio "
                                 "(leave it out for alpha = r)",
                                 norm(diff), radius));
    }
    Six z{};
    if (initial.has("fabric")) {
        z = initial.six_numbers("fabric");
        if (std::abs(trace(z)) > 1.0e-9 * std::max(1.0, norm(z))) {
            initial.fail("fabric", fmt::format("expected a deviatoric fabric tensor (z11 + z22 + "
                                               "z33 = 0), got trace {}",
                                               trace(z)));
        }
        if (norm(z) > p.z_max * (1.0 + 1.0e-9)) {
            initial.fail("fabric",
                         fmt::format("expected |z| <= z_max = {}, got |z| = {}", p.z_max, norm(z)));
        }
    }
    append(y, alpha);
    append(y, z);
    append(y, alpha); // alpha_in: the last load reversal is the start
}

} // namespace

std::vector<double> model_state(const TableReader& t, const MaterialSpec& material,
                                const Six& stress, double e) {
    // A model's own state keys are allowed for that model only (engine/model_registry.hpp).
    const std::vector<std::string_view> own = model_state_keys(material.model);
    for_each_model([&](auto m) {
        using M = decltype(m);
        for (std::string_view key : ModelEntry<M>::state_keys) {
            if (t.has(key) && std::find(own.begin(), own.end(), key) == own.end()) {
                t.fail(key, fmt::format("applies to {} only; expected no such key for model {}",
                                        M::name, material.model));
            }
        }
    });
    std::vector<double> y(stress.begin(), stress.end());
    y.push_back(e);
    if (const auto* p = std::get_if<HypoplasticityParams>(&material.choice)) {
        hypoplasticity_state(t, *p, stress, e, y);
    } else if (const auto* p = std::get_if<SanisandParams>(&material.choice)) {
        sanisand_state(t, *p, stress, e, y);
    }
    return y;
}

std::vector<double> read_initial_state(const TableReader& initial, const MaterialSpec& material) {
    if (initial.has("model_state")) {
        // A replay's exact state (io/element_test/element_replay.hpp): taken as it is, since
        // the model reached it.
        initial.allow_only({"model_state"});
        const auto n = static_cast<std::size_t>(state_size(material.choice));
        return initial.numbers(
            "model_state", n, Bounds::any(),
            fmt::format("values of the {} state (kernels/model_api.hpp layout)", material.model));
    }
    initial.allow_only({"stress", "void_ratio", "intergranular_strain", "back_stress", "fabric"});
    const Six stress = initial.six_numbers("stress");
    const double e = initial.number("void_ratio", Bounds::positive());
    return model_state(initial, material, stress, e);
}

} // namespace ifsim::io
