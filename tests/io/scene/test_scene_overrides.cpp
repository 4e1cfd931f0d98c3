// --set KEY=VALUE overrides: dotted paths, array entries counted from 1 (also inside arrays of
// tables), values parsed as TOML, and errors naming the file and the key.

#include <string>

#include <gtest/gtest.h>

#include "io/element_test/element_test_scene.hpp"
#include "io/scene/scene_error.hpp"
#include "io/scene/scene_toml.hpp"
#include "tests/io/scene_test_support.hpp"

namespace ifsim::io {
namespace {

ElementTestScene parse_with(const std::vector<std::string>& sets,
                            const std::string& text = test::valid_scene()) {
    const std::string file = test::write_scene(text);
    toml::table t = load_scene_table(file);
    for (const auto& s : sets) {
        apply_override(t, s, file);
    }
    return read_element_test_scene(t, file);
}

// The override (or the scene read after it) fails with a SceneError naming file and key.
void expect_error(const std::vector<std::string>& sets, const std::string& key,
                  const std::string& expected) {
    const std::string file = test::write_scene(test::valid_scene());
    try {
        toml::table t = load_scene_table(file);
        for (const auto& s : sets) {
            apply_override(t, s, file);
        }
        read_element_test_scene(t, file);
        FAIL() << "no error for " << key;
    } catch (const SceneError& e) {
        EXPECT_EQ(e.file(), file);
        EXPECT_EQ(e.key(), key) << e.what();
        EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
}

TEST(SceneOverrides, SetsATopLevelTableValue) {
    const ElementTestScene s = parse_with({"material.roughness=0.5"});
    EXPECT_DOUBLE_EQ(s.material.roughness, 0.5);
    EXPECT_DOUBLE_EQ(std::get<HypoplasticityParams>(s.material.choice).roughness, 0.5);
}

TEST(SceneOverrides, SetsAValueInsideAnArrayOfTables) {
    const ElementTestScene base = parse_with({});
    const ElementTestScene s = parse_with({"stage.2.deps_11=-0.01", "stage.1.steps=7"});
    EXPECT_DOUBLE_EQ(s.stages[1].change[0], -0.01);
    EXPECT_DOUBLE_EQ(base.stages[1].change[0], -0.002);
    EXPECT_EQ(s.stages[0].steps, 7);
    EXPECT_DOUBLE_EQ(s.stages[0].change[0], base.stages[0].change[0]);
    EXPECT_EQ(s.stages[1].steps, base.stages[1].steps);
}

TEST(SceneOverrides, SwitchesAComponentFromStrainToStressControl) {
    // Removing a key is not possible, so a switch is two steps: this is the documented error.
    expect_error({"stage.1.dsig_22=0.0"}, "stage.1", "found both");
}

TEST(SceneOverrides, ValuesAreParsedAsToml) {
    const ElementTestScene s = parse_with({"initial.stress=[-200, -100, -100, 0, 0, 0]",
                                           "initial.void_ratio = 0.65", "initial.stress.2=-120"});
    EXPECT_DOUBLE_EQ(s.initial_state[0], -200.0);
    EXPECT_DOUBLE_EQ(s.initial_state[1], -120.0);
    EXPECT_DOUBLE_EQ(s.initial_state[2], -100.0);
    EXPECT_DOUBLE_EQ(s.initial_state[6], 0.65);
}

TEST(SceneOverrides, BareWordsAreStrings) {
    const ElementTestScene s = parse_with({"material.model=sanisand"});
    EXPECT_EQ(s.material.model, "sanisand");
    EXPECT_EQ(s.initial_state.size(), 25u);
    const ElementTestScene q =
        parse_with({"material.parameters=\"l4c\"", "initial.void_ratio=0.9"});
    EXPECT_EQ(q.material.parameters, "l4c");
}

TEST(SceneOverrides, CreatesOptionalSections) {
    const ElementTestScene s =
        parse_with({"integration.tolerance=1e-5", "integration.tangent=rate"});
    EXPECT_DOUBLE_EQ(s.settings.update.settings.tolerance, 1e-5);
    EXPECT_EQ(s.settings.tangent, TangentKind::rate);
}

TEST(SceneOverrides, UnknownKeysAreErrors) {
    expect_error({"material.rougness=0.5"}, "material.rougness", "unknown key");
    expect_error({"stage.1.deps_44=0.5"}, "stage.1.deps_44", "unknown key");
    expect_error({"solver.tolerance=1"}, "solver", "unknown key");
}

TEST(SceneOverrides, BadPathsAndValuesAreErrors) {
    expect_error({"stage.3.steps=10"}, "stage.3.steps", "array of 2 entries");
    expect_error({"stage.0.steps=10"}, "stage.0.steps", "entry number from 1 to 2");
    expect_error({"stage[1].steps=10"}, "stage[1].steps", "counted from 1");
    expect_error({"material.roughness"}, "material.roughness", "KEY=VALUE");
    expect_error({"material.roughness=[1, 2"}, "material.roughness", "TOML value");
    expect_error({"material.parameters.phi_c=30"}, "material.parameters.phi_c",
                 "material.parameters is a string \"karlsruhe-sand\", not a table");
    expect_error({"initial.stress.7=1"}, "initial.stress.7", "array of 6 entries");
    expect_error({"material..model=x"}, "material..model", "without empty parts");
    expect_error({"material.roughness=2"}, "material.roughness", "in (0, 1]");
}

TEST(SceneOverrides, KeyOfAnAssignment) {
    EXPECT_EQ(override_key("material.roughness=0.5"), "material.roughness");
    EXPECT_EQ(override_key(" stage.2.steps = 3"), "stage.2.steps");
}

} // namespace
} // namespace ifsim::io
