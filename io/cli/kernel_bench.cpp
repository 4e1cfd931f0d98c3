#include "io/cli/kernel_bench.hpp"

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include <fmt/format.h>

#include "engine/batched_update.hpp"
#include "engine/model_registry.hpp"
#include "engine/sample_states.hpp"
#include "io/cli/interface_kernel_bench.hpp"
#include "io/cli/thread_limit.hpp"
#include "io/output/summary_writer.hpp"
#include "kernels/parameter_sets.hpp"

namespace ifsim::io {

namespace {

using Clock = std::chrono::steady_clock;

struct Timing {
    long updates = 0;
    double wall_s = 0.0;
    UpdateReport last;
    double substeps = 0.0;
    double rejected = 0.0;
    double rate_evaluations = 0.0;
};

template <class M>
Timing time_updates(const typename M::Params& params, const KernelBenchOptions& o) {
    MaterialPoints<M> mp(static_cast<std::size_t>(o.points));
    SampleSpec spec;
    spec.strain_increment = o.strain_increment;
    fill_samples(mp, params, spec);
    UpdateOptions opt;
    opt.simd = !o.scalar;
    opt.settings.scheme = o.scheme == "heun" ? IntegrationScheme::heun : IntegrationScheme::rkf23;
    opt.settings.tolerance = o.tolerance;
    opt.settings.split_internal = !o.no_split;
    opt.settings.backward_euler = o.implicit;

    Timing t;
    t.last = batched_update(mp, params, opt); // warm-up, untimed
    if constexpr (CarriesSubstep<M>) {
        if (!o.cold) { // the size the same increment ended with, as the next one would start
            std::copy_n(mp.trial(M::substep_index), mp.padded(), mp.committed(M::substep_index));
        }
    }
    const auto t0 = Clock::now();
    do {
        t.last = batched_update(mp, params, opt);
        ++t.updates;
        t.substeps += t.last.substeps;
        t.rejected += t.last.rejected;
        t.rate_evaluations += t.last.rate_evaluations;
        t.wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
    } while (t.wall_s < o.seconds);
    return t;
}

} // namespace

MaterialChoice kernel_bench_material(const KernelBenchOptions& o) {
    if (o.model == "hypoplasticity") {
        auto p = parameter_sets::hypoplasticity(o.parameters);
        if (!p) {
            throw std::invalid_argument(
                fmt::format("--parameters: no built-in hypoplasticity set \"{}\"; expected l4c or "
                            "karlsruhe-sand",
                            o.parameters));
        }
        p->roughness = o.roughness;
        p->prepare();
        return *p;
    }
    if (o.model == "sanisand") {
        auto p = parameter_sets::sanisand(o.parameters);
        if (!p) {
            throw std::invalid_argument(fmt::format(
                "--parameters: no built-in sanisand set \"{}\"; expected karlsruhe-sand",
                o.parameters));
        }
        p->roughness = o.roughness;
        p->prepare();
        return *p;
    }
    if (o.model == "linear-elastic") {
        LinearElasticParams p;
        p.prepare();
        return p;
    }
    throw std::invalid_argument(fmt::format(
        "--model: unknown model \"{}\"; expected hypoplasticity, sanisand or linear-elastic",
        o.model));
}

nlohmann::ordered_json run_kernel_bench(const KernelBenchOptions& o) {
    if (o.points < 1) {
        throw std::invalid_argument("--points: expected a number of points >= 1");
    }
    if (!(o.seconds > 0.0) || o.seconds > 3600.0) {
        throw std::invalid_argument("--seconds: expected a duration in (0, 3600] s");
    }
    if (!(o.roughness > 0.0 && o.roughness <= 1.0)) {
        throw std::invalid_argument("--roughness: expected kappa in (0, 1]");
    }
    if (!(o.strain_increment > 0.0 && o.strain_increment < 0.1)) {
        throw std::invalid_argument("--increment: expected a strain increment norm in (0, 0.1)");
    }
    if (o.scheme != "rkf23" && o.scheme != "heun") {
        throw std::invalid_argument(
            fmt::format("--scheme: unknown scheme \"{}\"; expected rkf23 or heun", o.scheme));
    }
    if (!(o.tolerance > 0.0 && o.tolerance < 0.5)) {
        throw std::invalid_argument("--tolerance: expected a relative tolerance in (0, 0.5)");
    }
    if (!o.formulation.empty() && o.formulation != "none") {
        return run_interface_kernel_bench(o);
    }
    if (o.model == "coulomb") {
        throw std::invalid_argument("--model coulomb: Coulomb friction is an interface model; "
                                    "expected --formulation coulomb with it");
    }
    if (o.implicit && o.model != "sanisand") {
        throw std::invalid_argument(fmt::format(
            "--implicit: backward-Euler steps exist for Sanisand only; expected --model "
            "sanisand, got \"{}\"",
            o.model));
    }
    const MaterialChoice material = kernel_bench_material(o);
    const ThreadLimit threads(o.threads);
    const Timing t = std::visit(
        [&](const auto& params) {
            using M = typename model_of<std::decay_t<decltype(params)>>::type;
            return time_updates<M>(params, o);
        },
        material);

    const double evaluations = static_cast<double>(t.updates) * static_cast<double>(o.points);
    nlohmann::ordered_json j;
    j["model"] = model_name(material);
    j["parameters"] = o.model == "linear-elastic" ? nlohmann::ordered_json(nullptr)
                                                  : nlohmann::ordered_json(o.parameters);
    j["formulation"] = nullptr;
    j["points"] = o.points;
    j["threads"] = threads.threads();
    j["path"] = o.scalar ? "scalar" : "simd";
    j["lanes"] = o.scalar ? std::size_t{1} : simd::lanes;
    j["roughness"] = o.roughness;
    j["strain_increment"] = o.strain_increment;
    j["committed"] = false;
    j["scheme"] = o.scheme;
    j["implicit"] = o.implicit;
    j["tolerance"] = o.tolerance;
    j["carried_substep"] = !o.cold;
    j["split_internal"] = !o.no_split;
    j["updates"] = t.updates;
    j["wall_s"] = t.wall_s;
    j["evaluations"] = static_cast<long long>(t.updates) * o.points;
    // Without an interface formulation a point update is one constitutive evaluation.
    j["evaluations_per_second"] = evaluations / t.wall_s;
    j["points_per_second"] = evaluations / t.wall_s;
    j["substeps_per_evaluation"] = t.substeps / evaluations;
    j["rejected_substeps_per_evaluation"] = t.rejected / evaluations;
    j["rate_evaluations_per_evaluation"] = t.rate_evaluations / evaluations;
    j["failed_points"] = t.last.failed;
    j["unreliable_points"] = t.last.unreliable;
    j["revision"] = build_revision();
    return j;
}

} // namespace ifsim::io
