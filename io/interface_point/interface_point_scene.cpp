#include "io/interface_point/interface_point_scene.hpp"

#include <array>
#include <span>

#include <fmt/format.h>

#include "io/interface_point/algorithm1_options.hpp"
#include "io/replay/replay_file.hpp"
#include "io/scene/interface_formulation_reader.hpp"
#include "io/scene/table_reader.hpp"

namespace ifsim::io {

namespace {

int model_state_size(const MaterialChoice& m) {
    return state_size(m);
}

// Up to three numbers of an optional key into the inputs from column `first`.
void read_inputs(const TableReader& t, std::string_view key, std::size_t count, int first,
                 FailedContactPoint& point, std::string_view meaning) {
    if (!t.has(key)) {
        return;
    }
    const std::vector<double> v = t.numbers(key, count, Bounds::any(), meaning);
    for (std::size_t k = 0; k < count; ++k) {
        point.inputs[static_cast<std::size_t>(first) + k] = v[k];
    }
}

} // namespace

InterfacePointScene read_interface_point_scene(const toml::table& table, const std::string& file) {
    const TableReader root(table, file, "");
    root.allow_only({"kind", "description", "interface", "algorithm1", "point", "increment"});
    InterfacePointScene scene;
    if (root.has("description")) {
        scene.description = root.string("description");
    }
    FailedContactPoint& p = scene.point;

    const TableReader iface = root.table("interface");
    iface.allow_only({"formulation", "model", "parameters", "roughness"});
    const std::string formulation = iface.choice_or("formulation", "novel", {"novel", "stutz"});
    const double roughness = iface.number_or("roughness", 0.9, Bounds::open_closed(0.0, 1.0));
    scene.material = read_model_and_parameters(iface, Hypoplasticity::name, true, roughness);
    p.model = scene.material.model;
    if (root.has("algorithm1")) {
        read_algorithm1(root.table("algorithm1"), p.options);
    }
    p.options.interface.formulation =
        formulation == "novel" ? InterfaceFormulation::novel : InterfaceFormulation::stutz;

    const TableReader point = root.table("point");
    point.allow_only({"ndim", "model_state", "normal_strain", "in_plane_strain", "shear_strain",
                      "last_subincrement"});
    p.ndim = static_cast<int>(point.integer_or("ndim", 3, 2, 3));
    p.options.interface.ndim = p.ndim;
    const auto ns = static_cast<std::size_t>(model_state_size(scene.material.choice));
    p.state = point.numbers(
        "model_state", ns, Bounds::any(),
        fmt::format("the {} state in local axes (kernels/model_api.hpp)", scene.material.model));
    p.state.push_back(point.number_or("normal_strain", 0.0));
    for (const char* key : {"in_plane_strain", "shear_strain"}) {
        const std::vector<double> v = point.has(key)
                                          ? point.numbers(key, 2, Bounds::any(), "components 1, 2")
                                          : std::vector<double>{0.0, 0.0};
        p.state.insert(p.state.end(), v.begin(), v.end());
    }
    p.state.push_back(point.number_or("last_subincrement", 0.0, Bounds::non_negative()));

    const TableReader inc = root.table("increment");
    inc.allow_only({"normal_traction", "penalty", "slip_increment", "in_plane_stress",
                    "in_plane_stress_slope", "normal", "tangent1", "tangent2", "subincrements"});
    p.inputs.fill(0.0);
    p.inputs[contact_col::t_N] = inc.number("normal_traction");
    p.inputs[contact_col::k_N] = inc.number_or("penalty", 1.0, Bounds::non_negative());
    read_inputs(inc, "slip_increment", 2, contact_col::dg1, p, "dg1, dg2 in m");
    if (formulation == "novel" && !inc.has("in_plane_stress")) {
        inc.fail("in_plane_stress", "missing; expected the in-plane targets [s_p1, s_p2] in kPa "
                                    "of the novel formulation (Eqs. 19-20)");
    }
    p.inputs[contact_col::s_p1] = p.inputs[contact_col::s_p2] = p.inputs[contact_col::t_N];
    read_inputs(inc, "in_plane_stress", 2, contact_col::s_p1, p, "s_p1, s_p2 in kPa");
    read_inputs(inc, "in_plane_stress_slope", 2, contact_col::dsp1_dtn, p, "d s_p / d t_N");
    const std::array<double, 9> frame = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    for (int k = 0; k < 9; ++k) {
        p.inputs[static_cast<std::size_t>(contact_col::n + k)] = frame[static_cast<std::size_t>(k)];
    }
    read_inputs(inc, "normal", 3, contact_col::n, p, "global components");
    read_inputs(inc, "tangent1", 3, contact_col::t1, p, "global components");
    read_inputs(inc, "tangent2", 3, contact_col::t2, p, "global components");
    p.inputs[contact_col::forced] = inc.integer_or("subincrements", 0, 0, 1000000000);
    return scene;
}

toml::table point_table(const FailedContactPoint& point, int model_state_size) {
    const std::span<const double> y(point.state);
    const auto ns = static_cast<std::size_t>(model_state_size);
    toml::table t;
    t.insert("ndim", point.ndim);
    t.insert("model_state", replay_numbers(y.first(ns)));
    t.insert("normal_strain", y[ns + contact_state::eps_n]);
    t.insert("in_plane_strain", replay_numbers(y.subspan(ns + contact_state::eps_p1, 2)));
    t.insert("shear_strain", replay_numbers(y.subspan(ns + contact_state::gamma1, 2)));
    t.insert("last_subincrement", y[ns + contact_state::last_sub]);
    return t;
}

toml::table increment_table(const FailedContactPoint& point) {
    const std::span<const double> in(point.inputs);
    toml::table t;
    t.insert("normal_traction", in[contact_col::t_N]);
    t.insert("penalty", in[contact_col::k_N]);
    t.insert("slip_increment", replay_numbers(in.subspan(contact_col::dg1, 2)));
    t.insert("in_plane_stress", replay_numbers(in.subspan(contact_col::s_p1, 2)));
    t.insert("in_plane_stress_slope", replay_numbers(in.subspan(contact_col::dsp1_dtn, 2)));
    t.insert("normal", replay_numbers(in.subspan(contact_col::n, 3)));
    t.insert("tangent1", replay_numbers(in.subspan(contact_col::t1, 3)));
    t.insert("tangent2", replay_numbers(in.subspan(contact_col::t2, 3)));
    t.insert("subincrements", static_cast<std::int64_t>(in[contact_col::forced]));
    return t;
}

} // namespace ifsim::io
