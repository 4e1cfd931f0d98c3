#pragma once
// Typed, checked reading of one TOML table of a scene. Every accessor either returns a valid
// value or throws SceneError naming the file, the full dotted key and what was expected; the
// reader knows its own path ("stage.2") so nested readers report full keys.

#include <array>
#include <initializer_list>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

namespace ifsim::io {

// An interval a number must lie in, with open or closed ends.
struct Bounds {
    double lo = -std::numeric_limits<double>::infinity();
    double hi = std::numeric_limits<double>::infinity();
    bool lo_open = false;
    bool hi_open = false;

    bool contains(double x) const;
    std::string describe() const; // "(0, 1]", "> 0", ">= 0", "any"

    static Bounds any() { return {}; }
    static Bounds positive() { return {0.0, std::numeric_limits<double>::infinity(), true, false}; }
    static Bounds non_negative() {
        return {0.0, std::numeric_limits<double>::infinity(), false, false};
    }
    static Bounds open_closed(double lo, double hi) { return {lo, hi, true, false}; }
    static Bounds open(double lo, double hi) { return {lo, hi, true, true}; }
    static Bounds closed_open(double lo, double hi) { return {lo, hi, false, true}; }
};

class TableReader {
public:
    // path: dotted path of this table ("" for the scene's root).
    TableReader(const toml::table& table, std::string file, std::string path);

    const std::string& file() const { return file_; }
    const std::string& path() const { return path_; }
    std::string key_path(std::string_view key) const;

    // Throws for the first key of the table that is not in `known`.
    void allow_only(std::initializer_list<std::string_view> known) const;
    void allow_only(const std::vector<std::string_view>& known) const;

    bool has(std::string_view key) const;
    const toml::node* find(std::string_view key) const;
    // Throws for the first of `keys` the table has, with `why` as the expected value (keys that
    // belong to another choice, e.g. another interface formulation).
    void reject(std::span<const std::string_view> keys, const std::string& why) const;

    double number(std::string_view key, const Bounds& bounds = Bounds::any()) const;
    double number_or(std::string_view key, double fallback,
                     const Bounds& bounds = Bounds::any()) const;
    long long integer(std::string_view key, long long lo, long long hi) const;
    long long integer_or(std::string_view key, long long fallback, long long lo,
                         long long hi) const;
    bool boolean_or(std::string_view key, bool fallback) const;
    std::string string(std::string_view key) const;
    // A string from a fixed set of choices.
    std::string choice_or(std::string_view key, std::string_view fallback,
                          std::initializer_list<std::string_view> choices) const;
    std::string choice_or(std::string_view key, std::string_view fallback,
                          std::span<const std::string_view> choices) const;
    // Six finite numbers in Voigt order 11 22 33 12 13 23.
    std::array<double, 6> six_numbers(std::string_view key) const;
    // `count` finite numbers within bounds (a coordinate, a size, a direction); `meaning` says
    // what they are in the message ("lower corner x, y in m").
    std::vector<double> numbers(std::string_view key, std::size_t count, const Bounds& bounds,
                                std::string_view meaning) const;
    // `count` integers from lo to hi.
    std::vector<long long> integers(std::string_view key, std::size_t count, long long lo,
                                    long long hi, std::string_view meaning) const;
    // The keys of this table, sorted (names of [material.NAME] tables).
    std::vector<std::string> keys() const;
    // The TOML table itself (for a reader that must outlive the parse, keep a copy of it).
    const toml::table& toml_table() const { return *table_; }
    TableReader table(std::string_view key) const;
    // Each entry of an array of tables ([[stage]]), with paths key.1, key.2, ...
    std::vector<TableReader> array_of_tables(std::string_view key) const;

    // Throws SceneError for key with the given expectation (located at the key's value if present).
    [[noreturn]] void fail(std::string_view key, const std::string& expected) const;
    // The same for a check that concerns the table as a whole (key = this table's path).
    [[noreturn]] void fail_here(const std::string& expected) const;

private:
    const toml::node& require(std::string_view key, std::string_view what) const;
    [[noreturn]] void wrong_type(std::string_view key, const toml::node& node,
                                 std::string_view what) const;

    const toml::table* table_;
    std::string file_;
    std::string path_;
};

} // namespace ifsim::io
