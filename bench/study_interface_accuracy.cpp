// Accuracy against cost of the interface knobs (design.md, "Accuracy and its cost"), measured
// on the paper's §5 simple interface shear tests at point level (engine/interface_test_driver.hpp):
//
//   mono-novel   monotonic CNL 100 kPa, novel formulation (paper Fig. 6)
//   mono-stutz   the same with the formulation of Stutz et al.
//   cyclic-novel CNS 300 kPa, K = 400 kPa/mm, amplitude 0.75 mm, novel (paper Fig. 7)
//
// Each knob is varied on its own around the engine's defaults (paper values, one polishing
// Newton step): max_subincrement, tolerance, polish_iterations, the contact Jacobian scheme,
// the perturbation theta, the continuum model's integration tolerance, the Newton Jacobian of
// Algorithm 1, plus a sweep of adaptive sub-increments over adaptive_tolerance. The error of
// a run is the largest deviation over the path from a fine reference at the same plate
// displacements, relative to the largest value of the reference:
//   err_tau = max |t_t1 - t_t1_ref| / max |t_t1_ref|,   err_un likewise for u_n.
// Cost: wall time, constitutive evaluations (interface lanes and sample), outer Newton
// iterations. A run that fails is recorded with its reason and the part of the path it did.
//
//   study_interface_accuracy --out docs            # full grid, docs/accuracy.{csv,json}
//   study_interface_accuracy --quick --out /tmp/q  # smoke run
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <tbb/global_control.h>

#include "engine/interface_test_driver.hpp"
#include "kernels/parameter_sets.hpp"
#include "kernels/simd.hpp"

#ifndef IFSIM_GIT_REVISION
#define IFSIM_GIT_REVISION "unknown"
#endif

using namespace ifsim;

namespace {

using Clock = std::chrono::steady_clock;

// ---------------------------------------------------------------------------------------------
// Command line

struct Options {
    std::string out;
    bool quick = false;
    int threads = 1;
    bool scalar = false;
    std::vector<std::string> cases = {"mono-novel", "mono-stutz", "cyclic-novel"};
    double mono_displacement = 0.002; // m
    int mono_steps = 200;
    int cyclic_cycles = 1;
    int cyclic_steps_per_quarter = 25;
    double cyclic_amplitude = 0.00075; // m
    double reference_factor = 10.0;    // reference max_subincrement = paper / factor
    std::vector<std::string> knobs;    // empty: all
    double reference_tolerance = 1.0e-8;
    double reference_model_tolerance = 1.0e-5;
    // Tighter step tolerances make the test driver cut steps (a different global path).
    double reference_step_tolerance = 1.0e-6;
    // Algorithm 1's Newton in the reference: the rate stiffness converges only linearly, so the
    // tight tolerance needs more than the default 30 iterations (or the driver cuts steps).
    bool reference_perturbation_jacobian = false;
    int reference_newton_iterations = 100;
    double tight_step_tolerance = 1.0e-6; // the test's Newton tolerance of the *_tight_step runs
    bool paths = false; // also write DIR/path_<test>.csv (reference and default paths)
};

[[noreturn]] void usage(int code) {
    std::printf(
        "Usage: study_interface_accuracy [options]\n"
        "  --out DIR            write DIR/accuracy.csv and DIR/accuracy.json\n"
        "  --quick              small grid and short paths (smoke run)\n"
        "  --threads N          TBB threads (default 1)\n"
        "  --scalar             scalar path of the contact engine and the sample (default SIMD)\n"
        "  --cases LIST         comma list of mono-novel, mono-stutz, cyclic-novel (default all)\n"
        "  --knobs LIST         only these knobs (default, max_subincrement, tolerance,\n"
        "                       polish_iterations, jacobian, theta, step_tolerance,\n"
        "                       max_subincrement_tight_step,\n"
        "                       model_tolerance, inner_jacobian, adaptive_tolerance,\n"
        "                       adaptive_tolerance_tight_step, adaptive_model_tolerance);\n"
        "                       the reference always runs\n"
        "  --mono-displacement M  plate displacement of the monotonic tests in m (default 0.002)\n"
        "  --mono-steps N       steps of the monotonic tests (default 200)\n"
        "  --cycles N           cycles of the cyclic test (default 1; 0: first quarter only)\n"
        "  --amplitude M        amplitude of the cyclic test in m (default 0.00075)\n"
        "  --quarter-steps N    steps per quarter cycle (default 25)\n"
        "  --reference-factor F reference sub-increment = 5e-6 / F (default 10)\n"
        "  --reference-tolerance T, --reference-model-tolerance T,\n"
        "  --reference-step-tolerance T  the reference's other settings (1e-8, 1e-5, 1e-6)\n"
        "  --reference-newton-iterations N  Algorithm 1's iteration limit there (100)\n"
        "  --reference-perturbation-jacobian  Algorithm 1's Newton Jacobian there by\n"
        "                       perturbation (default: rate stiffness)\n"
        "  --tight-step-tolerance T  the test's Newton tolerance of the runs at a tight one "
        "(1e-6)\n"
        "  --paths              also write DIR/path_TEST.csv: u_t1, t_t1, u_n of the reference\n"
        "                       and of the default run\n");
    std::exit(code);
}

std::vector<std::string> split(const std::string& s) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, ',')) {
        if (!item.empty()) {
            out.push_back(item);
        }
    }
    return out;
}

Options parse(int argc, char** argv) {
    Options o;
    bool steps_given = false, quarter_given = false, disp_given = false, cycles_given = false,
         factor_given = false, amplitude_given = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) {
                std::fprintf(stderr, "%s: missing value\n", a.c_str());
                usage(2);
            }
            return argv[++i];
        };
        auto number = [&]() {
            const std::string v = value();
            char* end = nullptr;
            const double d = std::strtod(v.c_str(), &end);
            if (end == v.c_str() || *end != '\0' || !std::isfinite(d) || d <= 0.0) {
                std::fprintf(stderr, "%s: expected a positive number, got '%s'\n", a.c_str(),
                             v.c_str());
                usage(2);
            }
            return d;
        };
        // Whole numbers >= lo.
        auto count = [&](int lo) {
            const std::string v = value();
            char* end = nullptr;
            const long n = std::strtol(v.c_str(), &end, 10);
            if (end == v.c_str() || *end != '\0' || n < lo || n > 1000000) {
                std::fprintf(stderr, "%s: expected a whole number >= %d, got '%s'\n", a.c_str(), lo,
                             v.c_str());
                usage(2);
            }
            return static_cast<int>(n);
        };
        if (a == "--out") {
            o.out = value();
        } else if (a == "--quick") {
            o.quick = true;
        } else if (a == "--threads") {
            o.threads = count(1);
        } else if (a == "--scalar") {
            o.scalar = true;
        } else if (a == "--cases") {
            o.cases = split(value());
        } else if (a == "--mono-displacement") {
            o.mono_displacement = number();
            disp_given = true;
        } else if (a == "--mono-steps") {
            o.mono_steps = count(1);
            steps_given = true;
        } else if (a == "--cycles") {
            o.cyclic_cycles = count(0);
            cycles_given = true;
        } else if (a == "--quarter-steps") {
            o.cyclic_steps_per_quarter = count(1);
            quarter_given = true;
        } else if (a == "--reference-tolerance") {
            o.reference_tolerance = number();
        } else if (a == "--reference-step-tolerance") {
            o.reference_step_tolerance = number();
        } else if (a == "--reference-perturbation-jacobian") {
            o.reference_perturbation_jacobian = true;
        } else if (a == "--reference-newton-iterations") {
            o.reference_newton_iterations = count(1);
        } else if (a == "--reference-model-tolerance") {
            o.reference_model_tolerance = number();
        } else if (a == "--tight-step-tolerance") {
            o.tight_step_tolerance = number();
        } else if (a == "--paths") {
            o.paths = true;
        } else if (a == "--knobs") {
            o.knobs = split(value());
        } else if (a == "--amplitude") {
            o.cyclic_amplitude = number();
            amplitude_given = true;
        } else if (a == "--reference-factor") {
            o.reference_factor = number();
            factor_given = true;
        } else if (a == "-h" || a == "--help") {
            usage(0);
        } else {
            std::fprintf(stderr, "unknown option '%s'\n", a.c_str());
            usage(2);
        }
    }
    for (const auto& c : o.cases) {
        if (c != "mono-novel" && c != "mono-stutz" && c != "cyclic-novel") {
            std::fprintf(stderr, "--cases: unknown case '%s'\n", c.c_str());
            usage(2);
        }
    }
    if (o.quick) {
        if (!disp_given) {
            o.mono_displacement = 0.0003;
        }
        if (!steps_given) {
            o.mono_steps = 30;
        }
        if (!cycles_given) {
            o.cyclic_cycles = 0;
        }
        if (!quarter_given) {
            o.cyclic_steps_per_quarter = 10;
        }
        if (!amplitude_given) {
            o.cyclic_amplitude = 0.0002;
        }
        if (!factor_given) {
            o.reference_factor = 4.0;
        }
    }
    return o;
}

// ---------------------------------------------------------------------------------------------
// The tests of paper §5

struct TestCase {
    std::string name;
    InterfaceTestSpec spec; // contact options filled per run
    std::string description;
};

std::vector<double> l4c_state(double normal_stress) {
    // Stress K0 = 0.5, e0 = 0.81, intergranular strain fully mobilised along the shearing.
    return {-normal_stress,
            -0.5 * normal_stress,
            -0.5 * normal_stress,
            0.0,
            0.0,
            0.0,
            0.81,
            0.0,
            0.0,
            0.0,
            7.0710678e-5,
            0.0,
            0.0};
}

TestCase make_case(const std::string& name, const Options& o) {
    TestCase tc;
    tc.name = name;
    auto sample = parameter_sets::hypoplasticity_l4c();
    sample.prepare();
    auto iface = parameter_sets::hypoplasticity_l4c();
    iface.roughness = 0.9;
    iface.prepare();
    InterfaceTestSpec& s = tc.spec;
    s.interface_material = iface;
    s.sample_material = sample;
    s.height = 0.02;
    if (name == "cyclic-novel") {
        s.interface_state = l4c_state(300.0);
        s.sample_state = l4c_state(300.0);
        s.control = NormalControl::constant_stiffness;
        s.normal_stiffness = 4.0e5; // 400 kPa/mm
        const double a = o.cyclic_amplitude;
        const int q = o.cyclic_steps_per_quarter;
        s.stages.push_back({q, a, 0.0});
        for (int c = 0; c < o.cyclic_cycles; ++c) {
            s.stages.push_back({2 * q, -2.0 * a, 0.0});
            s.stages.push_back({2 * q, 2.0 * a, 0.0});
        }
        s.stages.back().steps = q;
        s.stages.back().du_t1 = a;
        tc.description = fmt::format("CNS 300 kPa, K = 400 kPa/mm, amplitude {:g} mm, {} "
                                     "cycle(s) (0: first quarter), {} steps per quarter, novel",
                                     a * 1e3, o.cyclic_cycles, q);
    } else {
        s.interface_state = l4c_state(100.0);
        s.sample_state = l4c_state(100.0);
        s.control = NormalControl::constant_stress;
        s.stages.push_back({o.mono_steps, o.mono_displacement, 0.0});
        tc.description =
            fmt::format("CNL 100 kPa, u_t = {:g} mm in {} steps, {}", o.mono_displacement * 1e3,
                        o.mono_steps, name == "mono-novel" ? "novel" : "Stutz et al.");
    }
    return tc;
}

// ---------------------------------------------------------------------------------------------
// Knob settings

struct Setting {
    std::string knob;  // which knob differs from the defaults ("default", "reference", ...)
    std::string value; // its value as text
    ContactOptions contact;
    bool is_default = false; // engine defaults (paper values, polish 1)
    bool is_paper = false;   // paper: fixed 5e-6, tol 0.2 %, no polishing, Eq. 37, sqrt(EPS)
    double step_tolerance = InterfaceTestSpec{}.newton_tolerance; // the test's own Newton
};

ContactOptions base_contact(InterfaceFormulation f, const Options& o) {
    ContactOptions c;
    c.simd = !o.scalar;
    c.interface.formulation = f;
    c.interface.ndim = 3;
    c.interface.shear_band_thickness = 0.003;
    return c;
}

const char* jacobian_name(ContactJacobian j) {
    return contact_jacobian_names[static_cast<std::size_t>(j)].data();
}

std::string num(double v) {
    return fmt::format("{:g}", v);
}

// One knob at a time around the engine defaults, then the adaptive sweeps.
std::vector<Setting> make_settings(InterfaceFormulation f, const Options& o) {
    const ContactOptions def = base_contact(f, o);
    std::vector<Setting> out;
    out.push_back({"default", "engine", def, true, false});
    auto add = [&](const std::string& knob, const std::string& value, auto&& change) {
        Setting s{knob, value, def, false, false};
        change(s);
        out.push_back(std::move(s));
    };
    const bool q = o.quick;
    using V = std::vector<double>;
    for (double v : q ? V{2e-5, 1.25e-6} : V{4e-5, 2e-5, 1e-5, 2.5e-6, 1.25e-6}) {
        add("max_subincrement", num(v),
            [&](Setting& s) { s.contact.interface.max_subincrement = v; });
    }
    for (double v : q ? V{2e-2, 2e-6} : V{2e-2, 2e-4, 2e-5, 2e-6, 2e-7}) {
        add("tolerance", num(v), [&](Setting& s) { s.contact.interface.tolerance = v; });
    }
    add("polish_iterations", "0", [&](Setting& s) {
        s.contact.interface.polish_iterations = 0;
        s.is_paper = true; // every other value is the paper's
    });
    if (!q) {
        add("polish_iterations", "2",
            [&](Setting& s) { s.contact.interface.polish_iterations = 2; });
    }
    for (ContactJacobian j : {ContactJacobian::full_perturbation, ContactJacobian::analytical}) {
        add("jacobian", jacobian_name(j), [&](Setting& s) { s.contact.jacobian = j; });
    }
    for (double v : q ? V{1e-10} : V{1e-6, 1e-10}) {
        add("theta", num(v), [&](Setting& s) { s.contact.perturbation = v; });
    }
    for (double v : q ? V{o.tight_step_tolerance} : V{1e-3, o.tight_step_tolerance}) {
        add("step_tolerance", num(v), [&](Setting& s) { s.step_tolerance = v; });
    }
    // The sub-increment's own error, below the one the test's Newton leaves at its default
    // tolerance: the same sweep at the tight step tolerance (5e-6 is step_tolerance's run).
    if (!q) {
        for (double v : {4e-5, 2e-5, 1e-5}) {
            add("max_subincrement_tight_step", num(v), [&](Setting& s) {
                s.contact.interface.max_subincrement = v;
                s.step_tolerance = o.tight_step_tolerance;
            });
        }
    }
    if (!q) {
        for (double v : {1e-2, 1e-4}) {
            add("model_tolerance", num(v),
                [&](Setting& s) { s.contact.interface.model.tolerance = v; });
        }
        add("inner_jacobian", "perturbation", [&](Setting& s) {
            s.contact.interface.newton_jacobian = NewtonJacobian::perturbation;
        });
    }
    // Adaptive sub-increments (step doubling on the shear stress), at the test's default Newton
    // tolerance and at a tight one: the first shows what the outer Newton leaves behind.
    for (double step_tol : q ? V{o.tight_step_tolerance}
                             : V{InterfaceTestSpec{}.newton_tolerance, o.tight_step_tolerance}) {
        const bool tight = step_tol < InterfaceTestSpec{}.newton_tolerance;
        const V values = q       ? V{2e-3, 2e-5}
                         : tight ? V{2e-3, 2e-5, 2e-6}
                                 : V{2e-2, 2e-3, 2e-4, 2e-5, 2e-6};
        for (double v : values) {
            add(tight ? "adaptive_tolerance_tight_step" : "adaptive_tolerance", num(v),
                [&](Setting& s) {
                    s.contact.interface.adaptive = true;
                    s.contact.interface.adaptive_tolerance = v;
                    s.step_tolerance = step_tol;
                });
        }
    }
    // Adaptive sub-increments grow to whole steps, where the model's own integration error
    // (IntegrationSettings::tolerance) shows: adaptive at the tight step tolerance with tighter
    // model tolerances.
    if (!q) {
        for (double v : {1e-5}) {
            add("adaptive_model_tolerance", num(v), [&](Setting& s) {
                s.contact.interface.adaptive = true;
                s.step_tolerance = o.tight_step_tolerance;
                s.contact.interface.model.tolerance = v;
            });
        }
        for (double v : {2e-5, 2e-7}) {
            add("adaptive_inner_tolerance", num(v), [&](Setting& s) {
                s.contact.interface.adaptive = true;
                s.step_tolerance = o.tight_step_tolerance;
                s.contact.interface.tolerance = v;
                s.contact.interface.max_newton_iterations = 100;
            });
        }
    }
    return out;
}

Setting reference_setting(InterfaceFormulation f, const Options& o) {
    Setting s{"reference", "", base_contact(f, o), false, false};
    s.contact.interface.max_subincrement = 5.0e-6 / o.reference_factor;
    s.contact.interface.tolerance = o.reference_tolerance;
    s.contact.interface.polish_iterations = 1;
    s.contact.interface.model.tolerance = o.reference_model_tolerance;
    s.step_tolerance = o.reference_step_tolerance;
    s.contact.interface.newton_jacobian =
        o.reference_perturbation_jacobian ? NewtonJacobian::perturbation : NewtonJacobian::rate;
    s.contact.interface.max_newton_iterations = o.reference_newton_iterations;
    s.value = num(s.contact.interface.max_subincrement);
    return s;
}

// ---------------------------------------------------------------------------------------------
// Runs

struct Path {
    std::vector<double> u_t, t_t1, u_n;
};

struct RunRecord {
    std::string test;
    Setting setting;
    bool ok = true;
    std::string reason;
    int steps_total = 0, steps_done = 0;
    double err_tau = std::numeric_limits<double>::quiet_NaN();
    double err_un = std::numeric_limits<double>::quiet_NaN();
    double wall_s = 0.0, interface_s = 0.0, sample_s = 0.0;
    InterfaceTestCounters counters;
    Path path;
};

int total_steps(const InterfaceTestSpec& s) {
    int n = 0;
    for (const auto& st : s.stages) {
        n += st.steps;
    }
    return n;
}

RunRecord run_one(const TestCase& tc, const Setting& setting, const Options& o) {
    RunRecord r;
    r.test = tc.name;
    r.setting = setting;
    InterfaceTestSpec spec = tc.spec;
    spec.contact = setting.contact;
    spec.newton_tolerance = setting.step_tolerance;
    spec.sample_update.simd = !o.scalar;
    r.steps_total = total_steps(spec);
    const auto t0 = Clock::now();
    InterfaceTestResult res;
    try {
        res = run_interface_test(spec, [&](const InterfaceRow& row) {
            r.path.u_t.push_back(row.u_t1);
            r.path.t_t1.push_back(row.t_t1);
            r.path.u_n.push_back(row.u_n);
        });
    } catch (const std::exception& e) {
        res.ok = false;
        res.reason = e.what();
    }
    r.wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
    r.ok = res.ok;
    r.reason = res.reason;
    r.steps_done = static_cast<int>(r.path.u_t.size()) - 1;
    r.interface_s = res.interface_seconds;
    r.sample_s = res.sample_seconds;
    r.counters = res.counters;
    return r;
}

// Largest deviation along the common part of the paths, relative to the reference's largest
// magnitude. The plate displacements of both runs are checked to be the same.
void measure_error(RunRecord& r, const Path& ref) {
    const std::size_t n = std::min(r.path.u_t.size(), ref.u_t.size());
    double tmax = 0.0, umax = 0.0;
    for (std::size_t i = 0; i < ref.u_t.size(); ++i) {
        tmax = std::max(tmax, std::abs(ref.t_t1[i]));
        umax = std::max(umax, std::abs(ref.u_n[i]));
    }
    double et = 0.0, eu = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        if (std::abs(r.path.u_t[i] - ref.u_t[i]) > 1e-12) {
            throw std::logic_error("paths with different plate displacements");
        }
        et = std::max(et, std::abs(r.path.t_t1[i] - ref.t_t1[i]));
        eu = std::max(eu, std::abs(r.path.u_n[i] - ref.u_n[i]));
    }
    if (n > 1) {
        r.err_tau = et / std::max(tmax, 1e-30);
        r.err_un = eu / std::max(umax, 1e-30);
    }
}

// ---------------------------------------------------------------------------------------------
// Output

std::string csv_escape(const std::string& s) {
    std::string out = "\"";
    for (char c : s) {
        out += c == '"' ? std::string("\"\"") : std::string(1, c);
    }
    return out + "\"";
}

std::string fmt_num(double v) {
    return std::isfinite(v) ? fmt::format("{:.6g}", v) : std::string("nan");
}

struct Column {
    const char* name;
    std::function<std::string(const RunRecord&)> get;
};

std::vector<Column> columns() {
    auto I = [](const RunRecord& r) -> const InterfaceSettings& {
        return r.setting.contact.interface;
    };
    return {
        {"test", [](const RunRecord& r) { return r.test; }},
        {"knob", [](const RunRecord& r) { return r.setting.knob; }},
        {"value", [](const RunRecord& r) { return r.setting.value; }},
        {"is_default", [](const RunRecord& r) { return std::to_string(r.setting.is_default); }},
        {"is_paper", [](const RunRecord& r) { return std::to_string(r.setting.is_paper); }},
        {"max_subincrement", [=](const RunRecord& r) { return fmt_num(I(r).max_subincrement); }},
        {"tolerance", [=](const RunRecord& r) { return fmt_num(I(r).tolerance); }},
        {"polish_iterations",
         [=](const RunRecord& r) { return std::to_string(I(r).polish_iterations); }},
        {"jacobian", [](const RunRecord& r) { return jacobian_name(r.setting.contact.jacobian); }},
        {"theta", [](const RunRecord& r) { return fmt_num(r.setting.contact.perturbation); }},
        {"adaptive", [=](const RunRecord& r) { return std::to_string(I(r).adaptive); }},
        {"adaptive_tolerance",
         [=](const RunRecord& r) {
             return I(r).adaptive ? fmt_num(I(r).adaptive_tolerance) : std::string("");
         }},
        {"step_tolerance", [](const RunRecord& r) { return fmt_num(r.setting.step_tolerance); }},
        {"model_tolerance", [=](const RunRecord& r) { return fmt_num(I(r).model.tolerance); }},
        {"inner_jacobian",
         [=](const RunRecord& r) {
             return std::string(I(r).newton_jacobian == NewtonJacobian::rate ? "rate"
                                                                             : "perturbation");
         }},
        {"ok", [](const RunRecord& r) { return std::to_string(r.ok); }},
        {"steps_done", [](const RunRecord& r) { return std::to_string(r.steps_done); }},
        {"steps_total", [](const RunRecord& r) { return std::to_string(r.steps_total); }},
        {"err_tau", [](const RunRecord& r) { return fmt_num(r.err_tau); }},
        {"err_un", [](const RunRecord& r) { return fmt_num(r.err_un); }},
        {"wall_s", [](const RunRecord& r) { return fmt_num(r.wall_s); }},
        {"interface_s", [](const RunRecord& r) { return fmt_num(r.interface_s); }},
        {"sample_s", [](const RunRecord& r) { return fmt_num(r.sample_s); }},
        {"evaluations",
         [](const RunRecord& r) { return fmt_num(r.counters.constitutive_evaluations); }},
        {"interface_evaluations",
         [](const RunRecord& r) { return fmt_num(r.counters.interface_evaluations); }},
        {"sample_evaluations",
         [](const RunRecord& r) { return fmt_num(r.counters.sample_evaluations); }},
        {"subincrements", [](const RunRecord& r) { return fmt_num(r.counters.subincrements); }},
        {"step_cuts", [](const RunRecord& r) { return std::to_string(r.counters.step_cuts); }},
        {"outer_newton",
         [](const RunRecord& r) { return std::to_string(r.counters.newton_iterations); }},
        {"inner_newton",
         [](const RunRecord& r) { return fmt_num(r.counters.interface_newton_iterations); }},
        {"model_substeps", [](const RunRecord& r) { return fmt_num(r.counters.model_substeps); }},
        {"reason", [](const RunRecord& r) { return r.reason; }},
    };
}

void write_outputs(const Options& o, const std::vector<TestCase>& cases,
                   const std::vector<RunRecord>& runs, const std::string& command) {
    namespace fs = std::filesystem;
    fs::create_directories(o.out);
    const auto cols = columns();
    {
        std::ofstream f(fs::path(o.out) / "accuracy.csv");
        for (std::size_t c = 0; c < cols.size(); ++c) {
            f << (c ? "," : "") << cols[c].name;
        }
        f << "\n";
        for (const auto& r : runs) {
            for (std::size_t c = 0; c < cols.size(); ++c) {
                const std::string v = cols[c].get(r);
                f << (c ? "," : "") << (std::string(cols[c].name) == "reason" ? csv_escape(v) : v);
            }
            f << "\n";
        }
    }
    nlohmann::json j;
    j["command"] = command;
    j["revision"] = IFSIM_GIT_REVISION;
    j["threads"] = o.threads;
    j["simd"] = !o.scalar;
    j["simd_lanes"] = simd::lanes;
    j["reference"] = {
        {"max_subincrement", 5.0e-6 / o.reference_factor},
        {"tolerance", o.reference_tolerance},
        {"polish_iterations", 1},
        {"model_tolerance", o.reference_model_tolerance},
        {"step_tolerance", o.reference_step_tolerance},
        {"max_newton_iterations", o.reference_newton_iterations},
        {"inner_jacobian", o.reference_perturbation_jacobian ? "perturbation" : "rate"}};
    j["error_definition"] = "max over the path of |x - x_ref| / max |x_ref| at the same plate "
                            "displacements, x = t_t1 (err_tau) or u_n (err_un)";
    for (const auto& tc : cases) {
        j["tests"][tc.name] = tc.description;
    }
    nlohmann::json rows = nlohmann::json::array();
    for (const auto& r : runs) {
        nlohmann::json row;
        for (const auto& c : cols) {
            const std::string v = c.get(r);
            char* end = nullptr;
            const double d = std::strtod(v.c_str(), &end);
            if (!v.empty() && *end == '\0' && std::isfinite(d) && std::string(c.name) != "value") {
                row[c.name] = d;
            } else if (v == "nan") {
                row[c.name] = nullptr;
            } else {
                row[c.name] = v;
            }
        }
        rows.push_back(row);
    }
    j["runs"] = rows;
    std::ofstream f(fs::path(o.out) / "accuracy.json");
    f << j.dump(2) << "\n";
}

void write_path(const Options& o, const std::string& test, const Path& ref, const Path& def) {
    namespace fs = std::filesystem;
    fs::create_directories(o.out);
    std::ofstream f(fs::path(o.out) / ("path_" + test + ".csv"));
    f << "u_t1,t_t1_ref,u_n_ref,t_t1_default,u_n_default\n";
    for (std::size_t i = 0; i < ref.u_t.size(); ++i) {
        const bool d = i < def.u_t.size();
        f << fmt::format("{:.9g},{:.9g},{:.9g},{},{}\n", ref.u_t[i], ref.t_t1[i], ref.u_n[i],
                         d ? fmt_num(def.t_t1[i]) : "", d ? fmt_num(def.u_n[i]) : "");
    }
}

void print_progress(std::size_t i, std::size_t n, const RunRecord& r) {
    std::printf("[%2zu/%zu] %-12s %-18s %-17s %-4s err_tau %-9s err_un %-9s evals %-9s "
                "newton %-4ld cuts %-3ld wall %7.2f s%s%s\n",
                i, n, r.test.c_str(), r.setting.knob.c_str(), r.setting.value.c_str(),
                r.ok ? "ok" : "FAIL", fmt_num(r.err_tau).c_str(), fmt_num(r.err_un).c_str(),
                fmt_num(r.counters.constitutive_evaluations).c_str(), r.counters.newton_iterations,
                r.counters.step_cuts, r.wall_s, r.ok ? "" : "  ", r.ok ? "" : r.reason.c_str());
    std::fflush(stdout);
}

} // namespace

int main(int argc, char** argv) {
    const Options o = parse(argc, argv);
    std::string command = "study_interface_accuracy";
    for (int i = 1; i < argc; ++i) {
        command += std::string(" ") + argv[i];
    }
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                              static_cast<std::size_t>(std::max(1, o.threads)));

    std::vector<TestCase> cases;
    std::vector<std::vector<Setting>> grids;
    std::size_t n_runs = 0;
    for (const auto& name : o.cases) {
        cases.push_back(make_case(name, o));
        const auto f =
            name == "mono-stutz" ? InterfaceFormulation::stutz : InterfaceFormulation::novel;
        auto grid = make_settings(f, o);
        if (!o.knobs.empty()) {
            std::erase_if(grid, [&](const Setting& st) {
                return std::find(o.knobs.begin(), o.knobs.end(), st.knob) == o.knobs.end();
            });
        }
        grid.insert(grid.begin(), reference_setting(f, o));
        n_runs += grid.size();
        grids.push_back(std::move(grid));
    }
    std::printf("study_interface_accuracy: %zu runs, %s, %d thread(s)\n", n_runs,
                o.scalar ? "scalar" : fmt::format("SIMD ({} lanes)", simd::lanes).c_str(),
                o.threads);
    for (const auto& tc : cases) {
        std::printf("  %-12s %s\n", tc.name.c_str(), tc.description.c_str());
    }

    if (o.paths && o.out.empty()) {
        std::fprintf(stderr, "--paths needs --out DIR\n");
        return 2;
    }
    std::vector<RunRecord> runs;
    std::size_t i = 0;
    int failures = 0;
    for (std::size_t c = 0; c < cases.size(); ++c) {
        Path ref, def;
        for (const auto& setting : grids[c]) {
            RunRecord r = run_one(cases[c], setting, o);
            if (setting.knob == "reference") {
                if (!r.ok) {
                    std::printf("reference of %s failed: %s\n", cases[c].name.c_str(),
                                r.reason.c_str());
                }
                if (r.counters.step_cuts > 0) {
                    std::printf("warning: the reference of %s cut %ld steps (its global path "
                                "differs from the other runs')\n",
                                cases[c].name.c_str(), r.counters.step_cuts);
                }
                ref = r.path;
                r.err_tau = 0.0;
                r.err_un = 0.0;
            } else {
                measure_error(r, ref);
            }
            failures += r.ok ? 0 : 1;
            print_progress(++i, n_runs, r);
            if (setting.is_default) {
                def = r.path;
            }
            r.path = Path{}; // the paths are not kept
            runs.push_back(std::move(r));
        }
        if (o.paths) {
            write_path(o, cases[c].name, ref, def);
        }
    }
    std::printf("%d of %zu runs failed (recorded with their reason)\n", failures, n_runs);
    if (!o.out.empty()) {
        write_outputs(o, cases, runs, command);
        std::printf("wrote %s/accuracy.csv and %s/accuracy.json\n", o.out.c_str(), o.out.c_str());
    }
    return 0;
}
