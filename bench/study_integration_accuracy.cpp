// Accuracy against cost of the continuum models' explicit substepping (issue 13; results in
// docs/accuracy.md, "Continuum integration"), on element tests of hypoplasticity with
// intergranular strain (Karlsruhe sand, D_r = 70 %, e0 = 0.646):
//
//   triaxial   drained triaxial compression at sigma_3 = 100 kPa to eps_1 = -5 % (250 steps),
//              unloading by 0.2 % and reloading by 0.4 % (the intergranular strain at work)
//   oedometer  from K0 (-50, -25, -25 kPa): eps_1 -1 % in 100 steps, +0.3 % in 60, -0.4 % in 80
//   cyclic     undrained (isochoric) cyclic simple shear from K0 = 0.5 at 100 kPa, eps_12
//              amplitude 5e-4, 10 cycles, increments of 1e-5 (the kernel benchmark's size)
//
// Every run integrates the same path with one scheme (heun | rkf23), tolerance, h integrated on
// its own inside each substep (split_internal) or with the stress (then with a weight of h in
// the error measure), with or without the carried substep size. The error of a run is the
// largest deviation from a reference (rkf23 at 1e-10, not split, weight 1) over the
// path, relative to the largest stress of the reference: err_s = max |sigma - sigma_ref| /
// max |sigma_ref|; err_e = max |e - e_ref|. Cost: rate evaluations per constitutive update and
// the time inside the updates (one point, scalar path, one thread).
//
//   study_integration_accuracy --out docs     # docs/integration-accuracy.csv
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <tbb/global_control.h>

#include "engine/element_test_driver.hpp"
#include "kernels/parameter_sets.hpp"

using namespace ifsim;

namespace {

struct Test {
    std::string name;
    std::vector<double> initial;
    std::vector<ElementStage> stages;
};

ElementStage strain_stage(int steps, Sym<double> change) {
    ElementStage s;
    s.steps = steps;
    s.change = change;
    return s;
}

// Axial strain given, lateral stresses held (drained triaxial), shear strains zero.
ElementStage triaxial_stage(int steps, double deps1) {
    ElementStage s = strain_stage(steps, {deps1, 0.0, 0.0, 0.0, 0.0, 0.0});
    s.stress_controlled[1] = s.stress_controlled[2] = true;
    return s;
}

std::vector<double> state(const Sym<double>& stress, double e) {
    std::vector<double> y(Hypoplasticity::n_state, 0.0);
    for (int i = 0; i < 6; ++i) {
        y[static_cast<std::size_t>(i)] = stress[i];
    }
    y[6] = e;
    return y;
}

std::vector<Test> tests(double e0) {
    std::vector<Test> out;
    out.push_back(
        {"triaxial",
         state({-100.0, -100.0, -100.0, 0.0, 0.0, 0.0}, e0),
         {triaxial_stage(250, -0.05), triaxial_stage(20, 0.002), triaxial_stage(40, -0.004)}});
    out.push_back(
        {"oedometer",
         state({-50.0, -25.0, -25.0, 0.0, 0.0, 0.0}, e0),
         {strain_stage(100, {-0.01, 0, 0, 0, 0, 0}), strain_stage(60, {0.003, 0, 0, 0, 0, 0}),
          strain_stage(80, {-0.004, 0, 0, 0, 0, 0})}});
    Test cyclic{"cyclic", state({-150.0, -75.0, -75.0, 0.0, 0.0, 0.0}, e0), {}};
    const double amplitude = 5.0e-4;
    cyclic.stages.push_back(strain_stage(50, {0, 0, 0, amplitude, 0, 0}));
    for (int c = 0; c < 10; ++c) {
        cyclic.stages.push_back(strain_stage(100, {0, 0, 0, -2.0 * amplitude, 0, 0}));
        cyclic.stages.push_back(strain_stage(100, {0, 0, 0, 2.0 * amplitude, 0, 0}));
    }
    out.push_back(cyclic);
    return out;
}

struct Setting {
    std::string scheme = "rkf23";
    double tolerance = 1.0e-3;
    double weight = 1.0;
    bool carry = true;
    bool split = true;
};

struct Run {
    bool ok = false;
    std::string reason;
    std::vector<std::vector<double>> rows; // state per row
    double updates = 0.0;
    double rate_evaluations = 0.0;
    double substeps = 0.0;
    double rejected = 0.0;
    double seconds = 0.0;
};

Run run(const Test& t, const Setting& s) {
    ElementTestSettings es;
    es.update.simd = false;
    es.update.settings.scheme =
        s.scheme == "heun" ? IntegrationScheme::heun : IntegrationScheme::rkf23;
    es.update.settings.tolerance = s.tolerance;
    es.update.settings.state_error_weight = s.weight;
    es.update.settings.carry_substep = s.carry;
    es.update.settings.split_internal = s.split;
    es.tangent = TangentKind::rate; // the driver's Newton: no perturbed lanes in the cost
    es.max_newton_iterations = 200;
    auto params = *parameter_sets::hypoplasticity("karlsruhe-sand");
    params.prepare();
    Run r;
    const ElementTestResult res =
        run_element_test(params, t.initial, t.stages, es,
                         [&](const ElementRow& row) { r.rows.push_back(row.state); });
    r.ok = res.ok;
    r.reason = res.reason;
    r.updates = static_cast<double>(res.counters.constitutive_evaluations);
    r.rate_evaluations = res.counters.rate_evaluations;
    r.substeps = res.counters.substeps;
    r.rejected = res.counters.rejected_substeps;
    r.seconds = res.constitutive_seconds;
    return r;
}

struct Error {
    double stress = 0.0;
    double void_ratio = 0.0;
};

// Norm of a stress difference (Voigt, shear counted twice) between two flat states.
double stress_norm(const std::vector<double>& a, const std::vector<double>* b) {
    double d2 = 0.0;
    for (std::size_t i = 0; i < 6; ++i) {
        const double d = a[i] - (b ? (*b)[i] : 0.0);
        d2 += d * d * (i < 3 ? 1.0 : 2.0);
    }
    return std::sqrt(d2);
}

Error error(const Run& a, const Run& ref) {
    Error e;
    double scale = 1.0e-12;
    for (const auto& y : ref.rows) {
        scale = std::max(scale, stress_norm(y, nullptr));
    }
    const std::size_t n = std::min(a.rows.size(), ref.rows.size());
    for (std::size_t k = 0; k < n; ++k) {
        e.stress = std::max(e.stress, stress_norm(a.rows[k], &ref.rows[k]) / scale);
        e.void_ratio = std::max(e.void_ratio, std::abs(a.rows[k][6] - ref.rows[k][6]));
    }
    if (a.rows.size() < ref.rows.size()) { // a failed run: its error is unknown
        e.stress = e.void_ratio = std::nan("");
    }
    return e;
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"Accuracy against cost of the continuum models' substepping (element tests)"};
    std::string out = ".";
    bool quick = false;
    double reference_tolerance = 1.0e-10;
    app.add_option("--out", out, "Directory of integration-accuracy.csv")->capture_default_str();
    app.add_flag("--quick", quick, "Few settings (smoke run)");
    app.add_option("--reference-tolerance", reference_tolerance, "rkf23 tolerance of the reference")
        ->capture_default_str();
    CLI11_PARSE(app, argc, argv);
    tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 1);

    const double e0 = 0.646;
    std::vector<Setting> settings;
    const std::vector<double> tolerances =
        quick ? std::vector<double>{1.0e-3} : std::vector<double>{1e-2, 3e-3, 1e-3, 1e-4, 1e-5};
    for (const std::string scheme : {"heun", "rkf23"}) {
        for (double tol : tolerances) {
            for (bool carry : {false, true}) {
                settings.push_back({scheme, tol, 1.0, carry, true});
                for (double w : quick ? std::vector<double>{1.0} : std::vector<double>{1.0, 0.1}) {
                    settings.push_back({scheme, tol, w, carry, false});
                }
            }
        }
    }

    std::filesystem::create_directories(out);
    const std::string path = (std::filesystem::path(out) / "integration-accuracy.csv").string();
    std::ofstream csv(path + ".partial");
    csv << "test,scheme,split_internal,tolerance,state_error_weight,carry_substep,ok,err_stress,"
           "err_void_ratio,"
           "rate_evaluations_per_update,substeps_per_update,rejected_per_update,updates,"
           "ns_per_update\n";
    for (const Test& t : tests(e0)) {
        const Run ref = run(t, {"rkf23", reference_tolerance, 1.0, false, false});
        if (!ref.ok) {
            std::fprintf(stderr, "%s: the reference failed: %s\n", t.name.c_str(),
                         ref.reason.c_str());
            return 1;
        }
        std::fprintf(stderr, "%s: reference %zu rows, %.1f rate evaluations per update\n",
                     t.name.c_str(), ref.rows.size(), ref.rate_evaluations / ref.updates);
        for (const Setting& s : settings) {
            const Run r = run(t, s);
            const Error e = error(r, ref);
            const std::string line = fmt::format(
                "{},{},{},{:g},{:g},{},{},{:.3e},{:.3e},{:.3f},{:.3f},{:.3f},{:.0f},{:.0f}", t.name,
                s.scheme, s.split ? 1 : 0, s.tolerance, s.weight, s.carry ? 1 : 0, r.ok ? 1 : 0,
                e.stress, e.void_ratio, r.rate_evaluations / r.updates, r.substeps / r.updates,
                r.rejected / r.updates, r.updates, 1.0e9 * r.seconds / r.updates);
            csv << line << "\n";
            std::fprintf(stderr, "%s\n", line.c_str());
        }
    }
    csv.close();
    std::filesystem::rename(path + ".partial", path);
    std::printf("%s\n", path.c_str());
    return 0;
}
