#pragma once
// Helpers of the boundary-value scene tests: read a scene file (with --set overrides), expect
// the SceneError of a scene text (file, key, words of the message), replace a piece of text.

#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "io/boundary_value_scene.hpp"
#include "io/scene_error.hpp"
#include "io/scene_toml.hpp"
#include "tests/io/scene_test_support.hpp"

namespace ifsim::io::test {

inline BoundaryValueScene parse_boundary_value(const std::string& file,
                                               const std::vector<std::string>& sets = {}) {
    toml::table t = load_scene_table(file);
    for (const auto& s : sets) {
        apply_override(t, s, file);
    }
    return read_boundary_value_scene(t, file);
}

// The scene text must fail with a SceneError naming its file and `key`, with every one of
// `words` in the message.
inline void expect_boundary_value_error(const std::string& text, const std::string& key,
                                        const std::vector<std::string>& words) {
    const std::string file = write_scene(text);
    try {
        read_boundary_value_scene(load_scene_table(file), file);
        ADD_FAILURE() << "no error for key " << key;
    } catch (const SceneError& e) {
        EXPECT_EQ(e.key(), key) << e.what();
        EXPECT_EQ(e.file(), file);
        EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
        for (const auto& w : words) {
            EXPECT_NE(std::string(e.what()).find(w), std::string::npos) << w << "\n" << e.what();
        }
    }
}

inline void expect_boundary_value_error(const std::string& text, const std::string& key,
                                        const char* words) {
    expect_boundary_value_error(text, key, std::vector<std::string>{words});
}

// `text` with the first `from` replaced by `to` (a failed expectation when `from` is missing).
inline std::string replaced(std::string text, const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

} // namespace ifsim::io::test
