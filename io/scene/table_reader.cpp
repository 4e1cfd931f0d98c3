#include "io/scene/table_reader.hpp"

#include <cmath>

#include <fmt/format.h>

#include "io/scene/scene_error.hpp"
#include "io/scene/toml_describe.hpp"

namespace ifsim::io {

bool Bounds::contains(double x) const {
    const bool above = lo_open ? x > lo : x >= lo;
    const bool below = hi_open ? x < hi : x <= hi;
    return above && below;
}

std::string Bounds::describe() const {
    const bool lo_inf = std::isinf(lo);
    const bool hi_inf = std::isinf(hi);
    if (lo_inf && hi_inf) {
        return "any finite value";
    }
    if (hi_inf) {
        return fmt::format("{} {}", lo_open ? ">" : ">=", lo);
    }
    if (lo_inf) {
        return fmt::format("{} {}", hi_open ? "<" : "<=", hi);
    }
    return fmt::format("in {}{}, {}{}", lo_open ? "(" : "[", lo, hi, hi_open ? ")" : "]");
}

TableReader::TableReader(const toml::table& table, std::string file, std::string path)
    : table_(&table), file_(std::move(file)), path_(std::move(path)) {}

std::string TableReader::key_path(std::string_view key) const {
    return path_.empty() ? std::string(key) : fmt::format("{}.{}", path_, key);
}

void TableReader::allow_only(std::initializer_list<std::string_view> known) const {
    allow_only(std::vector<std::string_view>(known));
}

void TableReader::allow_only(const std::vector<std::string_view>& known) const {
    for (const auto& [k, v] : *table_) {
        bool ok = false;
        for (const auto& name : known) {
            ok = ok || k.str() == name;
        }
        if (!ok) {
            std::string list;
            for (const auto& name : known) {
                list += (list.empty() ? "" : ", ") + std::string(name);
            }
            throw SceneError(file_, key_path(k.str()),
                             fmt::format("unknown key; expected one of: {}", list),
                             line_in_file(v));
        }
    }
}

bool TableReader::has(std::string_view key) const {
    return table_->contains(key);
}

void TableReader::reject(std::span<const std::string_view> keys, const std::string& why) const {
    for (const std::string_view key : keys) {
        if (has(key)) {
            fail(key, why);
        }
    }
}

const toml::node* TableReader::find(std::string_view key) const {
    return table_->get(key);
}

void TableReader::fail(std::string_view key, const std::string& expected) const {
    const toml::node* n = find(key);
    throw SceneError(file_, key_path(key), expected, line_in_file(n ? *n : *table_));
}

void TableReader::fail_here(const std::string& expected) const {
    throw SceneError(file_, path_, expected, line_in_file(*table_));
}

const toml::node& TableReader::require(std::string_view key, std::string_view what) const {
    const toml::node* n = find(key);
    if (n == nullptr) {
        fail(key, fmt::format("missing; expected {}", what));
    }
    return *n;
}

void TableReader::wrong_type(std::string_view key, const toml::node& node,
                             std::string_view what) const {
    throw SceneError(file_, key_path(key),
                     fmt::format("expected {}, got {}", what, describe_node(node)),
                     line_in_file(node));
}

namespace {

// The value of a numeric node; false for any other node.
bool numeric_value(const toml::node& n, double& x) {
    if (const auto* i = n.as_integer()) {
        x = static_cast<double>(i->get());
        return true;
    }
    if (const auto* f = n.as_floating_point()) {
        x = f->get();
        return true;
    }
    return false;
}

} // namespace

double TableReader::number(std::string_view key, const Bounds& bounds) const {
    const std::string what = bounds.lo == -std::numeric_limits<double>::infinity() &&
                                     bounds.hi == std::numeric_limits<double>::infinity()
                                 ? std::string("a finite number")
                                 : fmt::format("a number {}", bounds.describe());
    const toml::node& n = require(key, what);
    double x = 0.0;
    if (!numeric_value(n, x)) {
        wrong_type(key, n, what);
    }
    if (!std::isfinite(x) || !bounds.contains(x)) {
        wrong_type(key, n, what);
    }
    return x;
}

double TableReader::number_or(std::string_view key, double fallback, const Bounds& bounds) const {
    return has(key) ? number(key, bounds) : fallback;
}

long long TableReader::integer(std::string_view key, long long lo, long long hi) const {
    const std::string what = fmt::format("an integer from {} to {}", lo, hi);
    const toml::node& n = require(key, what);
    const auto* i = n.as_integer();
    if (i == nullptr || i->get() < lo || i->get() > hi) {
        wrong_type(key, n, what);
    }
    return i->get();
}

long long TableReader::integer_or(std::string_view key, long long fallback, long long lo,
                                  long long hi) const {
    return has(key) ? integer(key, lo, hi) : fallback;
}

bool TableReader::boolean_or(std::string_view key, bool fallback) const {
    const toml::node* n = find(key);
    if (n == nullptr) {
        return fallback;
    }
    if (!n->is_boolean()) {
        wrong_type(key, *n, "true or false");
    }
    return n->as_boolean()->get();
}

std::string TableReader::string(std::string_view key) const {
    const toml::node& n = require(key, "a string");
    if (!n.is_string()) {
        wrong_type(key, n, "a string");
    }
    return n.as_string()->get();
}

std::string TableReader::choice_or(std::string_view key, std::string_view fallback,
                                   std::initializer_list<std::string_view> choices) const {
    return choice_or(key, fallback,
                     std::span<const std::string_view>(choices.begin(), choices.size()));
}

std::string TableReader::choice_or(std::string_view key, std::string_view fallback,
                                   std::span<const std::string_view> choices) const {
    std::string list;
    for (const auto& c : choices) {
        list += fmt::format("{}\"{}\"", list.empty() ? "" : " | ", c);
    }
    const std::string what = fmt::format("one of {}", list);
    const toml::node* n = find(key);
    if (n == nullptr) {
        if (fallback.empty()) {
            fail(key, fmt::format("missing; expected {}", what));
        }
        return std::string(fallback);
    }
    if (!n->is_string()) {
        wrong_type(key, *n, what);
    }
    const std::string value = n->as_string()->get();
    for (const auto& c : choices) {
        if (value == c) {
            return value;
        }
    }
    wrong_type(key, *n, what);
}

std::array<double, 6> TableReader::six_numbers(std::string_view key) const {
    constexpr std::string_view what = "an array of 6 finite numbers in Voigt order 11, 22, 33, "
                                      "12, 13, 23 (tensor shear components)";
    const toml::node& n = require(key, what);
    const auto* arr = n.as_array();
    if (arr == nullptr || arr->size() != 6) {
        wrong_type(key, n, what);
    }
    std::array<double, 6> v{};
    for (std::size_t i = 0; i < 6; ++i) {
        double x = 0.0;
        if (!numeric_value(*arr->get(i), x) || !std::isfinite(x)) {
            throw SceneError(file_, fmt::format("{}.{}", key_path(key), i + 1),
                             fmt::format("expected a finite number (entry {} of 6), got {}", i + 1,
                                         describe_node(*arr->get(i))),
                             line_in_file(n));
        }
        v[i] = x;
    }
    return v;
}

std::vector<double> TableReader::numbers(std::string_view key, std::size_t count,
                                         const Bounds& bounds, std::string_view meaning) const {
    const std::string what =
        fmt::format("an array of {} finite numbers {} ({})", count, bounds.describe(), meaning);
    const toml::node& n = require(key, what);
    const auto* arr = n.as_array();
    if (arr == nullptr || arr->size() != count) {
        wrong_type(key, n, what);
    }
    std::vector<double> v(count);
    for (std::size_t i = 0; i < count; ++i) {
        double x = 0.0;
        if (!numeric_value(*arr->get(i), x) || !std::isfinite(x) || !bounds.contains(x)) {
            throw SceneError(file_, fmt::format("{}.{}", key_path(key), i + 1),
                             fmt::format("expected a finite number {} (entry {} of {}: {}), got {}",
                                         bounds.describe(), i + 1, count, meaning,
                                         describe_node(*arr->get(i))),
                             line_in_file(n));
        }
        v[i] = x;
    }
    return v;
}

std::vector<long long> TableReader::integers(std::string_view key, std::size_t count, long long lo,
                                             long long hi, std::string_view meaning) const {
    const std::string what =
        fmt::format("an array of {} integers from {} to {} ({})", count, lo, hi, meaning);
    const toml::node& n = require(key, what);
    const auto* arr = n.as_array();
    if (arr == nullptr || arr->size() != count) {
        wrong_type(key, n, what);
    }
    std::vector<long long> v(count);
    for (std::size_t i = 0; i < count; ++i) {
        const auto* x = arr->get(i)->as_integer();
        if (x == nullptr || x->get() < lo || x->get() > hi) {
            throw SceneError(file_, fmt::format("{}.{}", key_path(key), i + 1),
                             fmt::format("expected an integer from {} to {} (entry {} of {}: {}), "
                                         "got {}",
                                         lo, hi, i + 1, count, meaning,
                                         describe_node(*arr->get(i))),
                             line_in_file(n));
        }
        v[i] = x->get();
    }
    return v;
}

std::vector<std::string> TableReader::keys() const {
    std::vector<std::string> out;
    for (const auto& [k, v] : *table_) {
        out.emplace_back(k.str());
    }
    return out;
}

TableReader TableReader::table(std::string_view key) const {
    const toml::node& n = require(key, "a table");
    if (!n.is_table()) {
        wrong_type(key, n, "a table");
    }
    return TableReader(*n.as_table(), file_, key_path(key));
}

std::vector<TableReader> TableReader::array_of_tables(std::string_view key) const {
    const std::string what = fmt::format("one or more tables [[{}]]", key_path(key));
    const toml::node& n = require(key, what);
    const auto* arr = n.as_array();
    if (arr == nullptr || arr->empty()) {
        wrong_type(key, n, what);
    }
    std::vector<TableReader> out;
    for (std::size_t i = 0; i < arr->size(); ++i) {
        const toml::node& entry = *arr->get(i);
        const std::string entry_path = fmt::format("{}.{}", key_path(key), i + 1);
        if (!entry.is_table()) {
            throw SceneError(file_, entry_path,
                             fmt::format("expected a table, got {}", describe_node(entry)),
                             line_in_file(entry));
        }
        out.emplace_back(*entry.as_table(), file_, entry_path);
    }
    return out;
}

} // namespace ifsim::io
