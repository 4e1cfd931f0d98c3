#include "io/replay/element_replay.hpp"

#include <fmt/format.h>

#include "io/replay/replay_file.hpp"

namespace ifsim::io {

namespace {

// Where the failed step starts: stage (0-based) and step in the stage (1-based).
struct FailedStep {
    std::size_t stage = 0;
    int k = 1;
    std::vector<double> state;
    Sym<double> guess{};
    Sym<double> stress_start{};
};

Sym<double> stress_of(const std::vector<double>& state) {
    Sym<double> s{};
    for (int j = 0; j < 6; ++j) {
        s[j] = state[static_cast<std::size_t>(j)];
    }
    return s;
}

// The driver's bookkeeping (engine/element_test_driver.cpp) after the last committed position.
FailedStep failed_step(const ElementTestScene& scene, const ElementRunOutcome& run) {
    FailedStep f;
    f.state = scene.initial_state;
    f.guess = scene.stages.front().first_guess;
    f.stress_start = stress_of(f.state);
    if (run.last) {
        const ElementTestPosition& p = *run.last;
        f.stage = static_cast<std::size_t>(p.stage);
        f.k = p.step_in_stage + 1;
        f.state = p.state;
        f.guess = p.guess;
        f.stress_start = p.stress_start;
        if (f.k > scene.stages[f.stage].steps) { // the next stage's first step
            ++f.stage;
            f.k = 1;
            f.guess = scene.stages[f.stage].first_guess;
            f.stress_start = stress_of(f.state);
        }
    }
    return f;
}

} // namespace

toml::table element_replay_scene(const toml::table& scene_table, const ElementTestScene& scene,
                                 const ElementRunOutcome& run) {
    const FailedStep f = failed_step(scene, run);
    const ElementStage& st = scene.stages[f.stage];
    const Sym<double> sigma = stress_of(f.state);
    toml::table stage;
    stage.insert("steps", 1);
    for (int j = 0; j < 6; ++j) {
        if (st.stress_controlled[j]) {
            // The run's target of this step, reached from the step's start stress.
            const double target = f.stress_start[j] + st.change[j] * f.k / st.steps;
            stage.insert(fmt::format("dsig_{}", voigt_suffix[j]), target - sigma[j]);
        } else {
            stage.insert(fmt::format("deps_{}", voigt_suffix[j]), st.change[j] / st.steps);
        }
    }
    stage.insert("first_guess", replay_numbers(f.guess));

    toml::table out;
    out.insert("kind", "element-test");
    out.insert("description",
               fmt::format("replay of the element-test step that failed: {}", run.result.reason));
    out.insert("material", *scene_table["material"].as_table());
    if (const toml::table* integration = scene_table["integration"].as_table()) {
        out.insert("integration", *integration);
    }
    toml::table initial;
    initial.insert("model_state", replay_numbers(f.state));
    out.insert("initial", std::move(initial));
    out.insert("stage", toml::array{std::move(stage)});
    return out;
}

std::filesystem::path write_element_replay(const std::filesystem::path& dir,
                                           const toml::table& scene_table,
                                           const ElementTestScene& scene,
                                           const ElementRunOutcome& run, bool simd) {
    return write_replay(dir, element_replay_scene(scene_table, scene, run),
                        "the material point of this element test failed in the step below", simd);
}

} // namespace ifsim::io
