#include "io/scene/scene_toml.hpp"

#include <charconv>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>
#include <vector>

#include <fmt/format.h>

#include "io/scene/scene_error.hpp"
#include "io/scene/toml_describe.hpp"

namespace ifsim::io {

namespace {

std::vector<std::string> split_path(std::string_view key) {
    std::vector<std::string> parts;
    std::size_t start = 0;
    while (true) {
        const std::size_t dot = key.find('.', start);
        parts.emplace_back(
            key.substr(start, dot == std::string_view::npos ? key.npos : dot - start));
        if (dot == std::string_view::npos) {
            break;
        }
        start = dot + 1;
    }
    return parts;
}

// A path segment that names an array entry: a positive integer (1 = first entry).
bool entry_number(const std::string& segment, std::size_t& number) {
    if (segment.empty()) {
        return false;
    }
    const auto [end, ec] = std::from_chars(segment.data(), segment.data() + segment.size(), number);
    return ec == std::errc() && end == segment.data() + segment.size();
}

std::string joined(const std::vector<std::string>& parts, std::size_t count) {
    std::string s;
    for (std::size_t i = 0; i < count; ++i) {
        s += (i ? "." : "") + parts[i];
    }
    return s;
}

// The VALUE of an override as a TOML node (moved out of a one-key document so that it keeps
// "--set" as its source).
toml::table parse_override_value(std::string_view text, const std::string& file,
                                 const std::string& key) {
    if (text.find('\n') != std::string_view::npos || text.find('\r') != std::string_view::npos) {
        throw SceneError(file, key, "expected a single-line TOML value after '=' in --set");
    }
    const std::string doc = fmt::format("value = {}", text);
    try {
        toml::table t = toml::parse(doc, override_source);
        if (t.size() == 1 && t.contains("value")) {
            return t;
        }
    } catch (const toml::parse_error&) {
        // fall through: maybe a bare word
    }
    // A bare word (letters, digits, - _ + . /) that is no TOML value is a string:
    // model=sanisand, normal.stiffness_unit=kPa/mm.
    const bool bare =
        !text.empty() && text.find_first_not_of("abcdefghijklmnopqrstuvwxyz"
                                                "ABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                                "0123456789-_+./") == std::string_view::npos;
    if (!bare) {
        throw SceneError(file, key,
                         fmt::format("expected a TOML value after '=' in --set (number, string, "
                                     "boolean, array such as [1.0, 2.0] or inline table), got '{}'",
                                     text));
    }
    return toml::parse(fmt::format("value = \"{}\"", text), override_source);
}

void place(toml::node& container, const std::string& segment, toml::node&& value,
           const std::string& file, const std::string& key, const std::string& container_path) {
    if (auto* tbl = container.as_table()) {
        std::move(value).visit([&](auto&& v) { tbl->insert_or_assign(segment, std::move(v)); });
        return;
    }
    auto* arr = container.as_array();
    std::size_t n = 0;
    if (!entry_number(segment, n) || n < 1 || n > arr->size()) {
        throw SceneError(file, key,
                         fmt::format("{} is an array of {} entries; expected an entry number "
                                     "from 1 to {} after it",
                                     container_path, arr->size(), arr->size()));
    }
    std::move(value).visit([&](auto&& v) { arr->replace(arr->begin() + (n - 1), std::move(v)); });
}

} // namespace

toml::table load_scene_table(const std::string& file) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec)) {
        throw SceneError(file, "", "cannot open the scene file; expected an existing TOML file");
    }
    std::ifstream in(file, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    if (!in || in.bad()) {
        throw SceneError(file, "", "cannot read the scene file");
    }
    return parse_scene_text(std::move(text).str(), file);
}

toml::table parse_scene_text(std::string_view text, const std::string& file) {
    try {
        return toml::parse(text, file);
    } catch (const toml::parse_error& err) {
        throw SceneError(file, "",
                         fmt::format("column {}: not valid TOML: {}", err.source().begin.column,
                                     err.description()),
                         static_cast<int>(err.source().begin.line));
    }
}

std::string override_key(std::string_view assignment) {
    const std::size_t eq = assignment.find('=');
    std::string_view key = assignment.substr(0, eq);
    while (!key.empty() && key.back() == ' ') {
        key.remove_suffix(1);
    }
    while (!key.empty() && key.front() == ' ') {
        key.remove_prefix(1);
    }
    return std::string(key);
}

void apply_override(toml::table& scene, std::string_view assignment, const std::string& file) {
    const std::size_t eq = assignment.find('=');
    const std::string key = override_key(assignment);
    if (eq == std::string_view::npos) {
        throw SceneError(file, key, "expected KEY=VALUE after --set (e.g. material.roughness=0.5)");
    }
    if (key.empty()) {
        throw SceneError(file, "",
                         fmt::format("--set '{}': expected a key before '='", assignment));
    }
    if (key.find_first_of("[]") != std::string::npos) {
        throw SceneError(file, key,
                         "expected a dotted path with array entries counted from 1, e.g. "
                         "stage.2.deps_11 (brackets are not part of the --set syntax)");
    }
    const std::vector<std::string> parts = split_path(key);
    for (const auto& p : parts) {
        if (p.empty()) {
            throw SceneError(file, key, "expected a dotted path without empty parts");
        }
    }
    std::string_view text = assignment.substr(eq + 1);
    while (!text.empty() && text.front() == ' ') {
        text.remove_prefix(1);
    }
    toml::table parsed = parse_override_value(text, file, key);

    toml::node* at = &scene;
    for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
        const std::string here = joined(parts, i + 1);
        toml::node* next = nullptr;
        if (auto* tbl = at->as_table()) {
            next = tbl->get(parts[i]);
            if (next == nullptr) {
                // An optional section that the file leaves out: create it.
                next = tbl->insert_or_assign(parts[i], toml::table{}).first->second.as_table();
            }
        } else {
            auto* arr = at->as_array();
            std::size_t n = 0;
            if (!entry_number(parts[i], n) || n < 1 || n > arr->size()) {
                throw SceneError(file, key,
                                 fmt::format("{} is an array of {} entries; expected an entry "
                                             "number from 1 to {} after it",
                                             joined(parts, i), arr->size(), arr->size()));
            }
            next = arr->get(n - 1);
        }
        if (!next->is_table() && !next->is_array()) {
            throw SceneError(file, key,
                             fmt::format("{} is {}, not a table or array, so it has no key '{}'",
                                         here, describe_node(*next), parts[i + 1]));
        }
        at = next;
    }
    place(*at, parts.back(), std::move(*parsed.get("value")), file, key,
          joined(parts, parts.size() - 1));
}

std::string scene_kind(const toml::table& scene, const std::string& file) {
    const toml::node* kind = scene.get("kind");
    if (kind == nullptr) {
        throw SceneError(file, "kind", "missing; expected kind = \"element-test\"");
    }
    if (!kind->is_string()) {
        throw SceneError(
            file, "kind",
            fmt::format("expected a string such as \"element-test\", got {}", describe_node(*kind)),
            line_in_file(*kind));
    }
    return kind->as_string()->get();
}

} // namespace ifsim::io
