#include "io/scene/material_parameters.hpp"

#include <numbers>

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

[[noreturn]] void unknown_set(const TableReader& material, const std::string& model,
                              const std::string& name, const char* known) {
    material.fail("parameters",
                  fmt::format("no built-in {} parameter set \"{}\"; expected one of {} or an "
                              "inline table [{}] with every value",
                              model, name, known, material.key_path("parameters")));
}

// The parameters of `model` from t's key "parameters" (a built-in set's name or an inline
// table); a missing key takes `default_set` unless that is empty.
MaterialSpec build_material(const TableReader& t, const std::string& model, double roughness,
                            bool intergranular_strain, std::string_view default_set) {
    MaterialSpec spec;
    spec.model = model;
    spec.roughness = roughness;
    const toml::node* given = t.find("parameters");
    if (given == nullptr && default_set.empty()) {
        t.fail("parameters", fmt::format("missing; expected the name of a built-in set (\"l4c\", "
                                         "\"karlsruhe-sand\") or an inline table [{}] with "
                                         "every value of the model",
                                         t.key_path("parameters")));
    }
    const bool by_name = given == nullptr || given->is_string();
    if (!by_name && !given->is_table()) {
        t.fail("parameters", "expected the name of a built-in set or a table of values");
    }
    spec.parameters = given == nullptr ? std::string(default_set)
                      : by_name        ? given->as_string()->get()
                                       : std::string("inline");

    if (spec.model == "hypoplasticity") {
        HypoplasticityParams p;
        if (by_name) {
            const auto set = parameter_sets::hypoplasticity(spec.parameters);
            if (!set) {
                unknown_set(t, spec.model, spec.parameters, "\"l4c\", \"karlsruhe-sand\"");
            }
            p = *set;
        } else {
            p = inline_hypoplasticity(t.table("parameters"));
        }
        p.intergranular_strain = intergranular_strain;
        p.roughness = spec.roughness;
        p.prepare();
        spec.choice = p;
    } else if (spec.model == "sanisand") {
        SanisandParams p;
        if (by_name) {
            const auto set = parameter_sets::sanisand(spec.parameters);
            if (!set) {
                unknown_set(t, spec.model, spec.parameters, "\"karlsruhe-sand\"");
            }
            p = *set;
        } else {
            p = inline_sanisand(t.table("parameters"));
        }
        p.roughness = spec.roughness;
        p.prepare();
        spec.choice = p;
    } else {
        if (by_name) {
            t.fail("parameters", fmt::format("linear-elastic has no built-in sets; expected an "
                                             "inline table [{}] with E (kPa) and nu",
                                             t.key_path("parameters")));
        }
        LinearElasticParams p = inline_linear_elastic(t.table("parameters"));
        p.prepare();
        spec.choice = p;
    }
    return spec;
}

} // namespace

MaterialSpec read_material(const TableReader& material) {
    material.allow_only({"model", "parameters", "roughness", "intergranular_strain"});
    const std::string model =
        material.choice_or("model", "", {"hypoplasticity", "sanisand", "linear-elastic"});
    const bool elastic = model == "linear-elastic";
    if (elastic && material.has("roughness")) {
        material.fail("roughness", "not used by linear-elastic; expected no roughness key");
    }
    const double roughness = material.number_or("roughness", 1.0, Bounds::open_closed(0.0, 1.0));
    if (model != "hypoplasticity" && material.has("intergranular_strain")) {
        material.fail("intergranular_strain",
                      "applies to hypoplasticity only; expected no such key for " + model);
    }
    return build_material(material, model, roughness,
                          material.boolean_or("intergranular_strain", true), "");
}

MaterialSpec read_model_and_parameters(const TableReader& table, std::string_view default_model,
                                       std::initializer_list<std::string_view> models,
                                       double roughness) {
    const std::string model = table.choice_or("model", default_model, models);
    std::string_view default_set;
    if (model == "hypoplasticity") {
        default_set = "l4c";
    } else if (model == "sanisand") {
        default_set = "karlsruhe-sand";
    }
    return build_material(table, model, roughness, true, default_set);
}

} // namespace ifsim::io
