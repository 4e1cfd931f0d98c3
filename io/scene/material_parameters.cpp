#include "io/scene/material_parameters.hpp"

#include <algorithm>
#include <numbers>
#include <span>

#include <fmt/format.h>

#include "kernels/parameter_sets.hpp"

namespace ifsim::io {

namespace {

constexpr double degree = std::numbers::pi / 180.0;

HypoplasticityParams inline_hypoplasticity(const TableReader& t) {
    t.allow_only({"phi_c", "h_s", "n", "e_i0", "e_c0", "e_d0", "alpha", "beta", "m_R", "m_T", "R",
                  "beta_R", "chi"});
    HypoplasticityParams p;
    p.phi_c = t.number("phi_c", Bounds::open(0.0, 90.0)) * degree;
    p.h_s = t.number("h_s", Bounds::positive());
    p.n = t.number("n", Bounds::open(0.0, 1.0));
    p.e_i0 = t.number("e_i0", Bounds::positive());
    p.e_c0 = t.number("e_c0", Bounds::positive());
    p.e_d0 = t.number("e_d0", Bounds::positive());
    if (!(p.e_d0 < p.e_c0 && p.e_c0 < p.e_i0)) {
        t.fail("e_c0", fmt::format("expected e_d0 < e_c0 < e_i0, got e_d0 = {}, e_c0 = {}, "
                                   "e_i0 = {}",
                                   p.e_d0, p.e_c0, p.e_i0));
    }
    p.alpha = t.number("alpha", Bounds::non_negative());
    p.beta = t.number("beta", Bounds::non_negative());
    p.m_R = t.number("m_R", Bounds::positive());
    p.m_T = t.number("m_T", Bounds::positive());
    p.R = t.number("R", Bounds::positive());
    p.beta_R = t.number("beta_R", Bounds::positive());
    p.chi = t.number("chi", Bounds::positive());
    return p;
}

SanisandParams inline_sanisand(const TableReader& t) {
    t.allow_only({"p_a", "e0", "lambda_c", "xi", "M_c", "c", "m", "G0", "nu", "h0", "c_h", "n_b",
                  "A0", "n_d", "z_max", "c_z"});
    SanisandParams p;
    p.p_a = t.number("p_a", Bounds::positive());
    p.e0 = t.number("e0", Bounds::positive());
    p.lambda_c = t.number("lambda_c", Bounds::non_negative());
    p.xi = t.number("xi", Bounds::positive());
    p.M_c = t.number("M_c", Bounds::positive());
    p.c = t.number("c", Bounds::open_closed(0.0, 1.0));
    p.m = t.number("m", Bounds::positive());
    p.G0 = t.number("G0", Bounds::positive());
    p.nu = t.number("nu", Bounds::closed_open(0.0, 0.5));
    p.h0 = t.number("h0", Bounds::positive());
    p.c_h = t.number("c_h", Bounds::non_negative());
    p.n_b = t.number("n_b", Bounds::non_negative());
    p.A0 = t.number("A0", Bounds::non_negative());
    p.n_d = t.number("n_d", Bounds::non_negative());
    p.z_max = t.number("z_max", Bounds::non_negative());
    p.c_z = t.number("c_z", Bounds::non_negative());
    if (p.m >= p.c * p.M_c) {
        t.fail("m", fmt::format("expected the yield cone m < c M_c = {} (inside the critical "
                                "state in extension), got m = {}",
                                p.c * p.M_c, p.m));
    }
    return p;
}

LinearElasticParams inline_linear_elastic(const TableReader& t) {
    t.allow_only({"E", "nu"});
    LinearElasticParams p;
    p.E = t.number("E", Bounds::positive());
    p.nu = t.number("nu", Bounds::open(-1.0, 0.5));
    return p;
}

// A list of names as a message: "a", "b".
std::string quoted(std::span<const std::string_view> names) {
    std::string list;
    for (const auto& n : names) {
        list += fmt::format("{}\"{}\"", list.empty() ? "" : ", ", n);
    }
    return list;
}

// The io side of a model entry (engine/model_registry.hpp): its inline parameter table and
// what a scene's material table adds to the parameters.
HypoplasticityParams read_inline(const TableReader& t, const Hypoplasticity&) {
    return inline_hypoplasticity(t);
}
SanisandParams read_inline(const TableReader& t, const Sanisand&) {
    return inline_sanisand(t);
}
LinearElasticParams read_inline(const TableReader& t, const LinearElastic&) {
    return inline_linear_elastic(t);
}
void complete(HypoplasticityParams& p, double roughness, bool intergranular_strain) {
    p.intergranular_strain = intergranular_strain;
    p.roughness = roughness;
}
void complete(SanisandParams& p, double roughness, bool) {
    p.roughness = roughness;
}
void complete(LinearElasticParams&, double, bool) {}

// The parameters of `model` from t's key "parameters" (a built-in set's name or an inline
// table); a missing key takes `default_set` unless that is empty.
MaterialSpec build_material(const TableReader& t, const std::string& model, double roughness,
                            bool intergranular_strain, std::string_view default_set) {
    MaterialSpec spec;
    spec.model = model;
    spec.roughness = roughness;
    const std::vector<std::string_view> sets = model_sets(model);
    const toml::node* given = t.find("parameters");
    if (given == nullptr && default_set.empty()) {
        const std::string by_set =
            sets.empty() ? "" : fmt::format("the name of a built-in set ({}) or ", quoted(sets));
        t.fail("parameters", fmt::format("missing; expected {}an inline table [{}] with every "
                                         "value of the model",
                                         by_set, t.key_path("parameters")));
    }
    const bool by_name = given == nullptr || given->is_string();
    if (!by_name && !given->is_table()) {
        t.fail("parameters", "expected the name of a built-in set or a table of values");
    }
    spec.parameters = given == nullptr ? std::string(default_set)
                      : by_name        ? given->as_string()->get()
                                       : std::string("inline");
    for_each_model([&](auto m) {
        using M = decltype(m);
        if (model != M::name) {
            return;
        }
        typename M::Params p;
        if (by_name && sets.empty()) {
            t.fail("parameters", fmt::format("{} has no built-in sets; expected an inline table "
                                             "[{}] with every value of the model",
                                             model, t.key_path("parameters")));
        }
        if (by_name) {
            const auto set = ModelEntry<M>::set(spec.parameters);
            if (!set) {
                t.fail("parameters",
                       fmt::format("no built-in {} parameter set \"{}\"; expected one of {} or "
                                   "an inline table [{}] with every value",
                                   model, spec.parameters, quoted(sets), t.key_path("parameters")));
            }
            p = *set;
        } else {
            p = read_inline(t.table("parameters"), m);
            spec.inline_parameters = *given->as_table();
        }
        complete(p, spec.roughness, intergranular_strain);
        p.prepare();
        spec.choice = p;
    });
    return spec;
}

} // namespace

MaterialSpec read_material(const TableReader& material) {
    material.allow_only({"model", "parameters", "roughness", "intergranular_strain"});
    const std::vector<std::string_view> models = model_names();
    const std::string model = material.choice_or("model", "", models);
    const std::vector<std::string_view> interface_models = model_names(true);
    const bool interface_model = std::find(interface_models.begin(), interface_models.end(),
                                           model) != interface_models.end();
    if (!interface_model && material.has("roughness")) {
        material.fail("roughness", "not used by " + model + "; expected no roughness key");
    }
    const double roughness = material.number_or("roughness", 1.0, Bounds::open_closed(0.0, 1.0));
    if (model != Hypoplasticity::name && material.has("intergranular_strain")) {
        material.fail("intergranular_strain",
                      "applies to hypoplasticity only; expected no such key for " + model);
    }
    return build_material(material, model, roughness,
                          material.boolean_or("intergranular_strain", true), "");
}

MaterialSpec read_model_and_parameters(const TableReader& table, std::string_view default_model,
                                       bool only_interface_models, double roughness) {
    const std::vector<std::string_view> models = model_names(only_interface_models);
    const std::string model = table.choice_or("model", default_model, models);
    const std::vector<std::string_view> sets = model_sets(model);
    return build_material(table, model, roughness, true, sets.empty() ? "" : sets.front());
}

} // namespace ifsim::io
