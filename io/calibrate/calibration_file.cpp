#include "io/calibrate/calibration_file.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "io/scene/scene_error.hpp"
#include "io/scene/scene_toml.hpp"
#include "io/scene/table_reader.hpp"
#include "io/scene/toml_describe.hpp"
#include "io/sweep/sweep_file.hpp"

namespace ifsim::io {

namespace fs = std::filesystem;

namespace {

fs::path existing_file(const TableReader& root, std::string_view key, const fs::path& folder) {
    const std::string name = root.string(key);
    const fs::path p = fs::path(name).is_absolute() ? fs::path(name) : folder / name;
    std::error_code ec;
    if (!fs::is_regular_file(p, ec)) {
        throw SceneError(root.file(), std::string(key),
                         fmt::format("an existing file (relative to the calibration file); {} is "
                                     "not one",
                                     p.string()),
                         line_in_file(*root.find(key)));
    }
    return p;
}

FittedParameter read_parameter(const TableReader& parameters, const std::string& key) {
    const std::string full = fmt::format("parameters.\"{}\"", key);
    const toml::node* node = parameters.find(key);
    if (!node->is_table()) {
        throw SceneError(parameters.file(), full,
                         "a table { initial = ..., bounds = [lower, upper] }", line_in_file(*node));
    }
    const TableReader p(*node->as_table(), parameters.file(), full);
    p.allow_only({"initial", "bounds"});
    FittedParameter f;
    f.key = key;
    f.initial = p.number("initial");
    const std::vector<double> b = p.numbers("bounds", 2, Bounds::any(), "lower and upper bound");
    f.lower = b[0];
    f.upper = b[1];
    if (!(f.lower < f.upper) || f.initial < f.lower || f.initial > f.upper) {
        throw SceneError(parameters.file(), full + ".bounds",
                         fmt::format("lower < upper with the initial value {} between them (got "
                                     "[{}, {}])",
                                     f.initial, f.lower, f.upper),
                         line_in_file(*node));
    }
    return f;
}

} // namespace

CalibrationFile read_calibration_file(const fs::path& path) {
    const std::string file = path.string();
    const toml::table table = load_scene_table(file);
    const TableReader root(table, file, "");
    root.allow_only({"scene", "data", "parameters", "set", "fit", "columns", "description"});
    CalibrationFile cal;
    cal.file = path;
    const fs::path folder = path.parent_path();
    cal.scene = root.string("scene");
    cal.scene_path = existing_file(root, "scene", folder);
    cal.data_path = existing_file(root, "data", folder);
    if (root.has("description")) {
        cal.description = root.string("description");
    }
    if (!root.has("parameters")) {
        throw SceneError(file, "parameters",
                         "a table of the keys to fit, e.g. \"interface.roughness\" = { initial = "
                         "0.8, bounds = [0.5, 1.0] }");
    }
    const TableReader parameters = root.table("parameters");
    for (const std::string& key : keys_in_file_order(parameters.toml_table())) {
        cal.parameters.push_back(read_parameter(parameters, key));
    }
    if (cal.parameters.empty()) {
        throw SceneError(file, "parameters", "at least one key to fit");
    }
    if (root.has("set")) {
        const toml::table& set = root.table("set").toml_table();
        for (const std::string& key : keys_in_file_order(set)) {
            for (const FittedParameter& p : cal.parameters) {
                if (p.key == key) {
                    throw SceneError(file, fmt::format("set.\"{}\"", key),
                                     "a key that is not also fitted in [parameters]");
                }
            }
            cal.fixed.push_back(key + "=" + toml_value_text(*set.get(key)));
        }
    }
    if (root.has("fit")) {
        const TableReader fit = root.table("fit");
        fit.allow_only({"weight_u_n", "max_iterations", "step"});
        cal.weight_u_n = fit.number_or("weight_u_n", cal.weight_u_n, Bounds::non_negative());
        cal.max_iterations = static_cast<int>(fit.integer_or("max_iterations", 30, 1, 10000));
        cal.step = fit.number_or("step", cal.step, Bounds::open(0.0, 0.5));
    }
    if (root.has("columns")) {
        const TableReader columns = root.table("columns");
        columns.allow_only({"u_t", "t_t", "u_n"});
        for (auto [key, target] : {std::pair{"u_t", &cal.column_u_t},
                                   {"t_t", &cal.column_t_t},
                                   {"u_n", &cal.column_u_n}}) {
            if (columns.has(key)) {
                *target = columns.string(key);
            }
        }
    }
    return cal;
}

} // namespace ifsim::io
