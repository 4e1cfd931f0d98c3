#include "io/sweep/sweep_file.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <fmt/format.h>

#include "io/scene/scene_error.hpp"
#include "io/scene/scene_toml.hpp"
#include "io/scene/table_reader.hpp"
#include "io/scene/toml_describe.hpp"

namespace ifsim::io {

namespace fs = std::filesystem;

namespace {

std::string double_text(double x) {
    if (std::isnan(x)) {
        return "nan";
    }
    if (std::isinf(x)) {
        return x > 0 ? "inf" : "-inf";
    }
    std::string s = fmt::format("{}", x);
    if (s.find_first_of(".e") == std::string::npos) {
        s += ".0"; // 1 would read back as an integer
    }
    return s;
}

std::string string_text(const std::string& s) {
    std::string out = "\"";
    for (const char c : s) {
        switch (c) {
        case '"':
            out += "\\\"";
            break;
        case '\\':
            out += "\\\\";
            break;
        case '\n':
            out += "\\n";
            break;
        case '\t':
            out += "\\t";
            break;
        default:
            if (static_cast<unsigned char>(c) < 0x20) {
                out += fmt::format("\\u{:04X}", static_cast<unsigned>(c));
            } else {
                out += c;
            }
        }
    }
    return out + "\"";
}

// What a table cell shows for a value: strings without their quotes.
std::string display_text(const toml::node& node) {
    if (const auto* s = node.as_string()) {
        return s->get();
    }
    return toml_value_text(node);
}

// A key of [grid] or [zip]: a non-empty list of values.
SweepAxis read_axis(const toml::table& section, const std::string& section_name,
                    const std::string& key, const std::string& file) {
    const toml::node& node = *section.get(key);
    const std::string full = fmt::format("{}.\"{}\"", section_name, key);
    const toml::array* values = node.as_array();
    if (values == nullptr || values->empty()) {
        throw SceneError(file, full,
                         fmt::format("a non-empty list of values for the scene key {} (got {})",
                                     key, describe_node(node)),
                         line_in_file(node));
    }
    if (override_key(key + "=0") != key || key.empty()) {
        throw SceneError(file, full, "a scene key (a dotted path such as interface.roughness)",
                         line_in_file(node));
    }
    SweepAxis axis{key, {}, {}};
    for (const toml::node& v : *values) {
        axis.values.push_back(toml_value_text(v));
        axis.display.push_back(display_text(v));
    }
    return axis;
}

std::vector<SweepAxis> read_axes(const TableReader& root, const std::string& name,
                                 const std::string& file) {
    std::vector<SweepAxis> axes;
    if (!root.has(name)) {
        return axes;
    }
    const toml::table& section = root.table(name).toml_table();
    for (const std::string& key : keys_in_file_order(section)) {
        axes.push_back(read_axis(section, name, key, file));
    }
    return axes;
}

} // namespace

std::string toml_value_text(const toml::node& node) {
    if (const auto* d = node.as_floating_point()) {
        return double_text(d->get());
    }
    if (const auto* i = node.as_integer()) {
        return fmt::format("{}", i->get());
    }
    if (const auto* b = node.as_boolean()) {
        return b->get() ? "true" : "false";
    }
    if (const auto* s = node.as_string()) {
        return string_text(s->get());
    }
    if (const auto* a = node.as_array()) {
        std::string out = "[";
        for (std::size_t i = 0; i < a->size(); ++i) {
            if (i > 0) {
                out += ", ";
            }
            out += toml_value_text(*a->get(i));
        }
        return out + "]";
    }
    if (const auto* t = node.as_table()) {
        std::string out = "{";
        bool first = true;
        for (const auto& [k, v] : *t) {
            out += fmt::format("{}{} = {}", first ? " " : ", ", string_text(std::string(k.str())),
                               toml_value_text(v));
            first = false;
        }
        return out + (first ? "}" : " }");
    }
    std::ostringstream s; // dates and times: TOML's own text
    node.visit([&](const auto& v) { s << v; });
    return s.str();
}

std::size_t SweepFile::runs() const {
    std::size_t n = scenes.size();
    for (const SweepAxis& a : grid) {
        n *= a.values.size();
    }
    if (!zip.empty()) {
        n *= zip.front().values.size();
    }
    return n;
}

SweepFile read_sweep_file(const fs::path& path) {
    const std::string file = path.string();
    const toml::table table = load_scene_table(file);
    const TableReader root(table, file, "");
    root.allow_only({"scene", "grid", "zip", "set", "description"});
    SweepFile sweep;
    sweep.file = path;
    const toml::node* scene = root.find("scene");
    if (scene == nullptr) {
        throw SceneError(file, "scene",
                         "the base scene file (a path relative to the sweep file, or a list of "
                         "them)");
    }
    if (const auto* s = scene->as_string()) {
        sweep.scenes.push_back(s->get());
    } else if (const auto* list = scene->as_array(); list != nullptr && !list->empty()) {
        for (const toml::node& n : *list) {
            if (!n.is_string()) {
                throw SceneError(file, "scene", "a list of scene file paths (strings)",
                                 line_in_file(n));
            }
            sweep.scenes.push_back(n.as_string()->get());
        }
    } else {
        throw SceneError(file, "scene",
                         fmt::format("a scene file path or a non-empty list of them (got {})",
                                     describe_node(*scene)),
                         line_in_file(*scene));
    }
    const fs::path folder = path.parent_path();
    for (const std::string& s : sweep.scenes) {
        const fs::path p = fs::path(s).is_absolute() ? fs::path(s) : folder / s;
        std::error_code ec;
        if (!fs::is_regular_file(p, ec)) {
            throw SceneError(file, "scene",
                             fmt::format("an existing scene file; {} is not one", p.string()),
                             line_in_file(*scene));
        }
        sweep.paths.push_back(p);
    }
    sweep.grid = read_axes(root, "grid", file);
    sweep.zip = read_axes(root, "zip", file);
    for (const SweepAxis& a : sweep.zip) {
        if (a.values.size() != sweep.zip.front().values.size()) {
            throw SceneError(file, fmt::format("zip.\"{}\"", a.key),
                             fmt::format("{} values, as many as zip.\"{}\" has (zipped lists go "
                                         "together entry by entry); it has {}",
                                         sweep.zip.front().values.size(), sweep.zip.front().key,
                                         a.values.size()));
        }
    }
    std::vector<std::string> swept;
    for (const auto* axes : {&sweep.grid, &sweep.zip}) {
        for (const SweepAxis& a : *axes) {
            if (std::find(swept.begin(), swept.end(), a.key) != swept.end()) {
                throw SceneError(file, a.key, "each key swept once (it is in [grid] and [zip])");
            }
            swept.push_back(a.key);
        }
    }
    if (root.has("set")) {
        const toml::table& set = root.table("set").toml_table();
        for (const std::string& key : keys_in_file_order(set)) {
            if (std::find(swept.begin(), swept.end(), key) != swept.end()) {
                throw SceneError(file, fmt::format("set.\"{}\"", key),
                                 "a key that is not also swept in [grid] or [zip]");
            }
            sweep.fixed.push_back(key + "=" + toml_value_text(*set.get(key)));
        }
    }
    return sweep;
}

} // namespace ifsim::io
