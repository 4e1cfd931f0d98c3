#include "io/scene/toml_describe.hpp"

#include <algorithm>
#include <limits>

#include <fmt/format.h>

#include "io/scene/scene_toml.hpp"

namespace ifsim::io {

std::string describe_node(const toml::node& node) {
    switch (node.type()) {
    case toml::node_type::string:
        return fmt::format("a string \"{}\"", node.as_string()->get());
    case toml::node_type::integer:
        return fmt::format("an integer {}", node.as_integer()->get());
    case toml::node_type::floating_point:
        return fmt::format("a number {}", node.as_floating_point()->get());
    case toml::node_type::boolean:
        return fmt::format("a boolean {}", node.as_boolean()->get());
    case toml::node_type::array:
        return fmt::format("an array of {} values", node.as_array()->size());
    case toml::node_type::table:
        return "a table";
    case toml::node_type::date:
    case toml::node_type::time:
    case toml::node_type::date_time:
        return "a date or time";
    default:
        return "nothing";
    }
}

bool from_override(const toml::node& node) {
    const auto& path = node.source().path;
    return path && *path == override_source;
}

int line_in_file(const toml::node& node) {
    if (from_override(node) || !node.source().path) {
        return 0;
    }
    return static_cast<int>(node.source().begin.line);
}

std::vector<std::string> keys_in_file_order(const toml::table& table) {
    std::vector<std::pair<std::string, int>> keys;
    for (const auto& [k, v] : table) {
        const int line = line_in_file(v);
        keys.emplace_back(std::string(k.str()), line > 0 ? line : std::numeric_limits<int>::max());
    }
    std::stable_sort(keys.begin(), keys.end(),
                     [](const auto& a, const auto& b) { return a.second < b.second; });
    std::vector<std::string> out;
    for (auto& k : keys) {
        out.push_back(std::move(k.first));
    }
    return out;
}

} // namespace ifsim::io
