#include "io/interface_point/algorithm1_options.hpp"

#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace ifsim::io {

namespace {

// The field list, walked by a writer and a reader: (key, field, bounds) for every option.
template <class Visitor>
void visit_options(ContactOptions& o, Visitor& v) {
    const double inf = std::numeric_limits<double>::infinity();
    InterfaceSettings& s = o.interface;
    v.number("shear_band_thickness", s.shear_band_thickness, Bounds::positive());
    v.number("max_subincrement", s.max_subincrement, Bounds::positive());
    v.number("tolerance", s.tolerance, Bounds::open(0.0, 1.0));
    v.flag("adaptive", s.adaptive);
    v.number("adaptive_tolerance", s.adaptive_tolerance, Bounds::open(0.0, 1.0));
    v.number("work_newton_iterations", s.work_newton_iterations, Bounds::non_negative());
    v.number("work_model_substeps", s.work_model_substeps, Bounds::non_negative());
    v.integer("max_newton_iterations", s.max_newton_iterations, 1, 10'000);
    v.integer("polish_iterations", s.polish_iterations, 0, 10);
    v.integer("max_subincrements", s.max_subincrements, 1, 1'000'000'000'000);
    v.number("min_subincrement", s.min_subincrement, Bounds::positive());
    v.number("max_model_substeps", s.max_model_substeps, Bounds::positive());
    v.choice("newton_jacobian", s.newton_jacobian,
             std::array<std::string_view, 2>{"rate", "perturbation"});
    v.number("newton_perturbation", s.newton_perturbation, Bounds::open(0.0, 1.0));
    v.flag("newton_fallback", s.newton_fallback);
    v.number("newton_switch_ratio", s.newton_switch_ratio, Bounds::closed_open(0.0, 1.0));
    v.flag("newton_switch_broyden", s.newton_switch_broyden);
    v.integer("newton_line_search", s.newton_line_search, 0, 60);
    v.number("min_band_fraction", s.min_band_fraction, Bounds::open(0.0, 1.0));
    v.number("max_normal_change", s.max_normal_change, Bounds::positive());
    v.number("open_threshold", s.open_threshold, Bounds::non_negative());
    v.flag("clamp_band", s.clamp_band);
    v.number("jacobian_tolerance", s.jacobian_tolerance, Bounds{0.0, 1.0, false, true});
    v.choice("jacobian", o.jacobian, contact_jacobian_names);
    v.number("perturbation", o.perturbation, Bounds::open(0.0, 1.0));
    IntegrationSettings& m = s.model;
    v.choice("model_scheme", m.scheme, std::array<std::string_view, 2>{"heun", "rkf23"});
    v.number("model_tolerance", m.tolerance, Bounds::open(0.0, 1.0));
    v.number("model_state_error_weight", m.state_error_weight, Bounds::non_negative());
    v.flag("model_carry_substep", m.carry_substep);
    v.flag("model_split_internal", m.split_internal);
    v.number("model_min_substep", m.min_substep, Bounds::open(0.0, 1.0));
    v.integer("model_max_substeps", m.max_substeps, 1, 100'000'000);
    v.number("model_min_pressure", m.min_pressure, Bounds::positive());
    v.number("model_max_step_growth", m.max_step_growth, Bounds{1.0, inf, false, false});
    v.number("model_min_step_shrink", m.min_step_shrink, Bounds::open(0.0, 1.0));
}

struct Writer {
    toml::table out;
    void number(std::string_view key, double x, const Bounds&) { out.insert(key, x); }
    void flag(std::string_view key, bool b) { out.insert(key, b); }
    template <class I>
    void integer(std::string_view key, I i, long long, long long) {
        out.insert(key, static_cast<std::int64_t>(i));
    }
    template <class E, std::size_t N>
    void choice(std::string_view key, E e, const std::array<std::string_view, N>& names) {
        out.insert(key, std::string(names[static_cast<std::size_t>(e)]));
    }
};

struct Reader {
    const TableReader& t;
    void number(std::string_view key, double& x, const Bounds& b) { x = t.number_or(key, x, b); }
    void flag(std::string_view key, bool& b) { b = t.boolean_or(key, b); }
    template <class I>
    void integer(std::string_view key, I& i, long long lo, long long hi) {
        i = static_cast<I>(t.integer_or(key, static_cast<long long>(i), lo, hi));
    }
    template <class E, std::size_t N>
    void choice(std::string_view key, E& e, const std::array<std::string_view, N>& names) {
        const std::string given = t.choice_or(key, names[static_cast<std::size_t>(e)],
                                              std::span<const std::string_view>(names));
        for (std::size_t k = 0; k < N; ++k) {
            if (names[k] == given) {
                e = static_cast<E>(k);
            }
        }
    }
};

// Key names, for allow_only.
struct Keys {
    std::vector<std::string_view> names;
    void number(std::string_view key, double, const Bounds&) { names.push_back(key); }
    void flag(std::string_view key, bool) { names.push_back(key); }
    template <class I>
    void integer(std::string_view key, I, long long, long long) {
        names.push_back(key);
    }
    template <class E, std::size_t N>
    void choice(std::string_view key, E, const std::array<std::string_view, N>&) {
        names.push_back(key);
    }
};

} // namespace

toml::table algorithm1_table(const ContactOptions& options) {
    ContactOptions copy = options;
    Writer w;
    visit_options(copy, w);
    return std::move(w.out);
}

void read_algorithm1(const TableReader& t, ContactOptions& options) {
    Keys keys;
    ContactOptions scratch;
    visit_options(scratch, keys);
    t.allow_only(keys.names);
    Reader r{t};
    visit_options(options, r);
}

} // namespace ifsim::io
