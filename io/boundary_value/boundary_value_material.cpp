#include "io/boundary_value/boundary_value_material.hpp"

#include <fmt/format.h>

#include "io/element_test/element_initial_state.hpp"

namespace ifsim::io {

namespace {

constexpr const char* k0_keys[] = {"k0", "surcharge", "unit_weight", "surface"};

bool any_k0_key(const TableReader& t) {
    for (const char* key : k0_keys) {
        if (t.has(key)) {
            return true;
        }
    }
    return false;
}

// fem's K0Stress from the table; the stress at the body's mid-height for the state's checks.
fem::K0Stress read_k0(const TableReader& t, const BodySpec& body, std::array<double, 6>& stress) {
    fem::K0Stress k;
    k.k0 = t.number("k0", Bounds::positive());
    k.surcharge = t.number_or("surcharge", 0.0, Bounds::non_negative());
    k.unit_weight = t.number_or("unit_weight", 0.0, Bounds::non_negative());
    k.surface = t.number_or("surface", body.top());
    const double z_mid = body.origin.back() + 0.5 * body.size.back();
    const double sv = -(k.surcharge + k.unit_weight * (k.surface - z_mid));
    if (!(sv < 0.0)) {
        t.fail(k.unit_weight > 0.0 ? "surface" : "surcharge",
               fmt::format("expected a compressive vertical stress in body \"{}\": sigma_v = "
                           "-(surcharge + unit_weight (surface - z)) at its mid-height z = {} is "
                           "{} kPa",
                           body.name, z_mid, sv));
    }
    const double sh = k.k0 * sv;
    stress = body.origin.size() == 2 ? std::array<double, 6>{sh, sv, sh, 0.0, 0.0, 0.0}
                                     : std::array<double, 6>{sh, sh, sv, 0.0, 0.0, 0.0};
    return k;
}

} // namespace

BodyMaterial read_body_material(const TableReader& t, const BodySpec& body) {
    t.allow_only({"model", "parameters", "density", "void_ratio", "stress", "k0", "surcharge",
                  "unit_weight", "surface", "intergranular_strain", "back_stress", "fabric"});
    BodyMaterial m;
    m.spec = read_model_and_parameters(t, "", false, 1.0);
    const bool elastic = m.spec.model == LinearElastic::name;
    m.set.element_set = body.name;
    m.set.material = m.spec.choice;
    m.set.density = t.number_or("density", 0.0, Bounds::non_negative());

    if (t.has("stress") && any_k0_key(t)) {
        t.fail("stress", "expected either a uniform stress or the geostatic keys k0, surcharge, "
                         "unit_weight, surface, not both");
    }
    if (t.has("stress")) {
        m.stress = t.six_numbers("stress");
    } else if (any_k0_key(t)) {
        m.set.k0 = read_k0(t, body, m.stress);
        m.geostatic = true;
    } else if (!elastic) {
        t.fail("stress", fmt::format("missing; expected the initial stress of model {}: a uniform "
                                     "stress = [6 values in kPa, global axes] or k0 = K0 with "
                                     "surcharge and/or unit_weight (geostatic)",
                                     m.spec.model));
    }
    m.void_ratio = elastic ? t.number_or("void_ratio", 1.0, Bounds::positive())
                           : t.number("void_ratio", Bounds::positive());
    m.set.initial_state = model_state(t, m.spec, m.stress, m.void_ratio);
    return m;
}

} // namespace ifsim::io
