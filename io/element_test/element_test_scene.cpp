#include "io/element_test/element_test_scene.hpp"

#include <fmt/format.h>

#include "io/element_test/element_initial_state.hpp"
#include "io/scene/integration_scheme_reader.hpp"
#include "io/scene/table_reader.hpp"

namespace ifsim::io {

namespace {

ElementStage read_stage(const TableReader& t) {
    t.allow_only({"steps", "deps_11", "deps_22", "deps_33", "deps_12", "deps_13", "deps_23",
                  "dsig_11", "dsig_22", "dsig_33", "dsig_12", "dsig_13", "dsig_23", "first_guess"});
    ElementStage stage;
    stage.steps = static_cast<int>(t.integer("steps", 1, 100'000'000));
    for (int j = 0; j < 6; ++j) {
        const std::string deps = fmt::format("deps_{}", voigt_suffix[j]);
        const std::string dsig = fmt::format("dsig_{}", voigt_suffix[j]);
        const bool strain = t.has(deps);
        const bool stress = t.has(dsig);
        if (strain == stress) {
            t.fail_here(fmt::format("component {}: expected exactly one of {} (change of the "
                                    "strain over the stage) and {} (change of the stress, kPa); "
                                    "found {}",
                                    voigt_suffix[j], deps, dsig, strain ? "both" : "neither"));
        }
        stage.stress_controlled[j] = stress;
        stage.change[j] = stress ? t.number(dsig) : t.number(deps);
    }
    if (t.has("first_guess")) {
        stage.first_guess = t.six_numbers("first_guess");
    }
    return stage;
}

ElementTestSettings read_settings(const TableReader& root) {
    ElementTestSettings s;
    if (!root.has("integration")) {
        return s;
    }
    const TableReader t = root.table("integration");
    t.allow_only({"tolerance", "tangent", "newton_tolerance", "max_newton_iterations",
                  "perturbation", "min_pressure", "max_substeps", "scheme"});
    IntegrationSettings& is = s.update.settings;
    is.scheme = read_integration_scheme(t, "scheme", is.scheme);
    is.tolerance = t.number_or("tolerance", is.tolerance, Bounds::open(0.0, 1.0));
    is.min_pressure = t.number_or("min_pressure", is.min_pressure, Bounds::positive());
    is.max_substeps =
        static_cast<int>(t.integer_or("max_substeps", is.max_substeps, 1, 100'000'000));
    s.tangent = t.choice_or("tangent", "perturbation", {"perturbation", "rate"}) == "rate"
                    ? TangentKind::rate
                    : TangentKind::perturbation;
    s.newton_tolerance =
        t.number_or("newton_tolerance", s.newton_tolerance, Bounds::open(0.0, 1.0));
    s.max_newton_iterations =
        static_cast<int>(t.integer_or("max_newton_iterations", s.max_newton_iterations, 1, 10'000));
    s.perturbation = t.number_or("perturbation", s.perturbation, Bounds::open(0.0, 1.0));
    return s;
}

} // namespace

long ElementTestScene::total_steps() const {
    long n = 0;
    for (const auto& s : stages) {
        n += s.steps;
    }
    return n;
}

ElementTestScene read_element_test_scene(const toml::table& scene, const std::string& file) {
    const TableReader root(scene, file, "");
    root.allow_only({"kind", "description", "material", "initial", "stage", "integration"});
    ElementTestScene out;
    if (root.has("description")) {
        out.description = root.string("description");
    }
    out.material = read_material(root.table("material"));
    out.initial_state = read_initial_state(root.table("initial"), out.material);
    for (const TableReader& st : root.array_of_tables("stage")) {
        out.stages.push_back(read_stage(st));
    }
    out.settings = read_settings(root);
    return out;
}

} // namespace ifsim::io
