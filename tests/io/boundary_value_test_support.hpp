#pragma once
// Helpers of the boundary-value scene tests: read a scene file (with --set overrides), expect
// the SceneError of a scene text (file, key, words of the message), replace a piece of text.

#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include "io/boundary_value/boundary_value_scene.hpp"
#include "io/scene/scene_error.hpp"
#include "io/scene/scene_toml.hpp"
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

// A run folder's history.csv (every value as text) and summary.json.
struct History {
    std::vector<std::string> names;
    std::vector<std::map<std::string, std::string>> rows;
    double number(std::size_t row, const std::string& c) const {
        return std::stod(rows[row].at(c));
    }
};

inline History read_history(const std::filesystem::path& dir) {
    std::istringstream in(test::read_text(dir / "history.csv"));
    History h;
    std::string line;
    std::getline(in, line);
    std::istringstream hs(line);
    for (std::string n; std::getline(hs, n, ',');) {
        h.names.push_back(n);
    }
    while (std::getline(in, line)) {
        std::map<std::string, std::string> row;
        std::size_t k = 0, start = 0;
        for (;; ++k) {
            const std::size_t comma = line.find(',', start);
            row[h.names.at(k)] = line.substr(start, comma - start);
            if (comma == std::string::npos) {
                break;
            }
            start = comma + 1;
        }
        EXPECT_EQ(k + 1, h.names.size()) << line;
        h.rows.push_back(row);
    }
    return h;
}

inline nlohmann::json summary(const std::filesystem::path& dir) {
    return nlohmann::json::parse(test::read_text(dir / "summary.json"));
}

// `text` with the first `from` replaced by `to` (a failed expectation when `from` is missing).
inline std::string replaced(std::string text, const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

} // namespace ifsim::io::test
