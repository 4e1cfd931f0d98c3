#include "io/cli/interface_kernel_bench.hpp"

#include <chrono>
#include <cmath>
#include <random>
#include <stdexcept>
#include <type_traits>

#include <fmt/format.h>

#include "engine/contact_update.hpp"
#include "engine/coulomb_contact.hpp"
#include "engine/sample_states.hpp"
#include "io/cli/thread_limit.hpp"
#include "io/output/summary_writer.hpp"

namespace ifsim::io {

namespace {

using Clock = std::chrono::steady_clock;

constexpr int bench_ndim = 3;
// Normal penalty k_N (kPa/m): a typical value; it scales the normal perturbation lanes only.
constexpr double bench_penalty = 1.0e6;

double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

// A random right-handed orthonormal frame (n, t1, t2).
void random_frame(std::mt19937_64& rng, double n[3], double t1[3], double t2[3]) {
    std::normal_distribution<double> g(0.0, 1.0);
    double len = 0.0;
    do {
        for (int d = 0; d < 3; ++d) {
            n[d] = g(rng);
        }
        len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    } while (len < 1.0e-3);
    for (int d = 0; d < 3; ++d) {
        n[d] /= len;
    }
    // t1 = a x n / |a x n| with a the global axis least aligned with n.
    const int k = std::abs(n[0]) < std::abs(n[1]) ? (std::abs(n[0]) < std::abs(n[2]) ? 0 : 2)
                                                  : (std::abs(n[1]) < std::abs(n[2]) ? 1 : 2);
    double a[3] = {0.0, 0.0, 0.0};
    a[k] = 1.0;
    t1[0] = a[1] * n[2] - a[2] * n[1];
    t1[1] = a[2] * n[0] - a[0] * n[2];
    t1[2] = a[0] * n[1] - a[1] * n[0];
    const double l1 = std::sqrt(t1[0] * t1[0] + t1[1] * t1[1] + t1[2] * t1[2]);
    for (int d = 0; d < 3; ++d) {
        t1[d] /= l1;
    }
    t2[0] = n[1] * t1[2] - n[2] * t1[1];
    t2[1] = n[2] * t1[0] - n[0] * t1[2];
    t2[2] = n[0] * t1[1] - n[1] * t1[0];
}

// A tangential gap increment of size in [0.5, 1.5] x `typical`, in a random direction.
void random_gap(std::mt19937_64& rng, double typical, double& dg1, double& dg2) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const double size = typical * (0.5 + u(rng));
    const double angle = 2.0 * 3.14159265358979323846 * u(rng);
    dg1 = size * std::cos(angle);
    dg2 = size * std::sin(angle);
}

// A valid interface state of model M from a sampled continuum state: the interface stress of
// Eq. 17 has no in-plane shear; Sanisand's back stress is put back on the axis of that stress.
template <class M>
StateVec<double, M::n_state> interface_state(const typename M::Params& p, std::mt19937_64& rng) {
    StateVec<double, M::n_state> y = sample_state(p, rng);
    y[5] = 0.0;
    if constexpr (std::is_same_v<M, Sanisand>) {
        y = Sanisand::initial_state(stress_of(y), y[state_index::void_ratio]);
    }
    return y;
}

struct Totals {
    long updates = 0;
    double wall_s = 0.0;
    double evaluations = 0.0; // constitutive evaluations, perturbed lanes included
    double lanes = 0.0;
    double subincrements = 0.0;
    double newton_iterations = 0.0;
    std::size_t failed = 0; // of the last repetition
    std::size_t open = 0;
    std::size_t slipping = 0;
};

template <class M>
Totals time_contact(const typename M::Params& params, const KernelBenchOptions& o) {
    const auto n = static_cast<std::size_t>(o.points);
    ContactPoints<M> cp(n, bench_ndim);
    std::mt19937_64 rng(12345);
    for (std::size_t i = 0; i < n; ++i) {
        const auto y = interface_state<M>(params, rng);
        cp.set_state(i, y);
        double nv[3], t1[3], t2[3];
        random_frame(rng, nv, t1, t2);
        cp.set_frame(i, nv, t1, t2);
        cp.input(contact_col::t_N)[i] = y[0];
        cp.input(contact_col::k_N)[i] = bench_penalty;
        cp.input(contact_col::s_p1)[i] = y[1];
        cp.input(contact_col::s_p2)[i] = y[2];
        random_gap(rng, o.gap_increment, cp.input(contact_col::dg1)[i],
                   cp.input(contact_col::dg2)[i]);
    }
    ContactOptions opt;
    opt.simd = !o.scalar;
    opt.interface.formulation =
        o.formulation == "novel" ? InterfaceFormulation::novel : InterfaceFormulation::stutz;
    opt.interface.ndim = bench_ndim;
    opt.interface.shear_band_thickness = o.shear_band_thickness;
    opt.interface.adaptive = o.subincrement == "adaptive";
    contact_jacobian_from_name(o.jacobian, opt.jacobian); // checked by the caller
    ContactEngine<M> engine;
    Totals t;
    engine.update(cp, params, opt); // warm-up, untimed
    const auto t0 = Clock::now();
    do {
        const ContactReport rep = engine.update(cp, params, opt);
        ++t.updates;
        t.evaluations += rep.constitutive_evaluations;
        t.lanes += rep.lanes;
        t.subincrements += rep.subincrements;
        t.newton_iterations += rep.newton_iterations;
        t.failed = rep.failed;
        t.open = rep.open;
        t.wall_s = seconds_since(t0);
    } while (t.wall_s < o.seconds);
    return t;
}

Totals time_coulomb(const KernelBenchOptions& o, const CoulombParams& p) {
    const auto n = static_cast<std::size_t>(o.points);
    CoulombContactPoints cp(n, bench_ndim);
    std::mt19937_64 rng(12345);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (std::size_t i = 0; i < n; ++i) {
        const double t_N = -(20.0 + 380.0 * u(rng));
        // Shear traction anywhere inside the cone: the increments leave some points sticking,
        // others slipping.
        const double tau = p.friction_coefficient * -t_N * u(rng);
        const double angle = 2.0 * 3.14159265358979323846 * u(rng);
        cp.set_traction(i, tau * std::cos(angle), tau * std::sin(angle));
        cp.input(coulomb_col::t_N)[i] = t_N;
        cp.input(coulomb_col::k_N)[i] = bench_penalty;
        random_gap(rng, o.gap_increment, cp.input(coulomb_col::dg1)[i],
                   cp.input(coulomb_col::dg2)[i]);
        double nv[3], t1[3], t2[3];
        random_frame(rng, nv, t1, t2);
        cp.set_frame(i, nv, t1, t2);
    }
    CoulombContactOptions opt;
    opt.simd = !o.scalar;
    Totals t;
    coulomb_contact_update(cp, p, opt); // warm-up, untimed
    const auto t0 = Clock::now();
    do {
        const CoulombContactReport rep = coulomb_contact_update(cp, p, opt);
        ++t.updates;
        t.evaluations += rep.evaluations;
        t.lanes += static_cast<double>(rep.points);
        t.open = rep.open;
        t.slipping = rep.slipping;
        t.wall_s = seconds_since(t0);
    } while (t.wall_s < o.seconds);
    return t;
}

} // namespace

nlohmann::ordered_json run_interface_kernel_bench(const KernelBenchOptions& o) {
    const bool coulomb = o.formulation == "coulomb";
    if (!coulomb && o.formulation != "novel" && o.formulation != "stutz") {
        throw std::invalid_argument(
            fmt::format("--formulation {}: expected none, novel, stutz or coulomb", o.formulation));
    }
    if (ContactJacobian j; !contact_jacobian_from_name(o.jacobian, j)) {
        throw std::invalid_argument(fmt::format(
            "--jacobian {}: expected {}", o.jacobian,
            fmt::join(contact_jacobian_names.begin(), contact_jacobian_names.end(), ", ")));
    }
    if (o.subincrement != "fixed" && o.subincrement != "adaptive") {
        throw std::invalid_argument(
            fmt::format("--subincrement {}: expected fixed or adaptive", o.subincrement));
    }
    if (coulomb && (o.jacobian != "perturbation" || o.subincrement != "fixed")) {
        throw std::invalid_argument("--jacobian and --subincrement tune Algorithm 1 of the "
                                    "novel and stutz formulations; Coulomb friction always uses "
                                    "its exact analytical Jacobian and no sub-increments");
    }
    if (!(o.gap_increment > 0.0 && o.gap_increment < 1.0e-2)) {
        throw std::invalid_argument("--gap-increment: expected a tangential gap increment in "
                                    "(0, 0.01) m");
    }
    if (!(o.shear_band_thickness > 0.0 && o.shear_band_thickness < 1.0)) {
        throw std::invalid_argument("--shear-band-thickness: expected d_s0 in (0, 1) m");
    }

    nlohmann::ordered_json j;
    Totals t;
    const ThreadLimit threads(o.threads);
    if (coulomb) {
        const CoulombParams p; // mu = 0.25, k_t = 6000 kPa/m (paper §6.1)
        // The Coulomb law has no continuum model; --model is reported as given.
        if (o.model != "coulomb") {
            kernel_bench_material(o); // still a known model name
        }
        t = time_coulomb(o, p);
        j["model"] = o.model;
        j["interface_model"] = "coulomb";
        j["parameters"] = nullptr;
        j["friction_coefficient"] = p.friction_coefficient;
        j["tangential_stiffness"] = p.tangential_stiffness;
    } else {
        if (o.model == "linear-elastic" || o.model == "coulomb") {
            throw std::invalid_argument(fmt::format(
                "--model {}: the {} formulation uses a continuum model as interface model; "
                "expected hypoplasticity or sanisand",
                o.model, o.formulation));
        }
        const MaterialChoice material = kernel_bench_material(o);
        t = std::visit(
            [&](const auto& params) {
                using M = typename model_of<std::decay_t<decltype(params)>>::type;
                return time_contact<M>(params, o);
            },
            material);
        j["model"] = model_name(material);
        j["interface_model"] = model_name(material);
        j["parameters"] = o.parameters;
        j["roughness"] = o.roughness;
        j["shear_band_thickness"] = o.shear_band_thickness;
        j["jacobian"] = o.jacobian;
        j["subincrement"] = o.subincrement;
    }
    const double point_updates = static_cast<double>(t.updates) * static_cast<double>(o.points);
    // Reordered so the contract's fields come first.
    nlohmann::ordered_json out;
    out["model"] = j["model"];
    out["formulation"] = o.formulation;
    out["points"] = o.points;
    out["threads"] = threads.threads();
    out["path"] = o.scalar ? "scalar" : "simd";
    out["evaluations_per_second"] = t.evaluations / t.wall_s;
    out["points_per_second"] = point_updates / t.wall_s;
    out["lanes_per_point"] = t.lanes / point_updates;
    out["subincrements_per_point"] = t.subincrements / point_updates;
    out["newton_iterations_per_point"] = t.newton_iterations / point_updates;
    out["evaluations_per_point"] = t.evaluations / point_updates;
    for (const auto& [key, value] : j.items()) {
        if (!out.contains(key)) {
            out[key] = value;
        }
    }
    out["ndim"] = bench_ndim;
    out["gap_increment"] = o.gap_increment;
    out["lanes"] = o.scalar ? std::size_t{1} : simd::lanes;
    out["committed"] = false;
    out["updates"] = t.updates;
    out["wall_s"] = t.wall_s;
    out["evaluations"] = t.evaluations;
    out["failed_points"] = t.failed;
    out["open_points"] = t.open;
    if (coulomb) {
        out["slipping_points"] = t.slipping;
    }
    out["revision"] = build_revision();
    return out;
}

} // namespace ifsim::io
