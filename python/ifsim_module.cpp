// The compiled part of the Python module `ifsim` (python/ifsim/__init__.py is the rest): the
// ifsim command line run in-process, and Python values turned into TOML (a scene given as a
// dict, --set values given as Python values).

#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <toml++/toml.h>

#include "io/cli/cli.hpp"
#include "io/output/summary_writer.hpp"
#include "io/sweep/sweep_file.hpp"

namespace py = pybind11;

namespace {

toml::array to_array(const py::handle& list, const std::string& where);
toml::table to_table(const py::dict& dict, const std::string& where);

// One Python value as a TOML node; `where` names it in errors ("scene.material.roughness").
template <class Insert>
void insert_value(const py::handle& v, const std::string& where, Insert insert) {
    if (py::isinstance<py::bool_>(v)) { // before int: bool is an int in Python
        insert(toml::value<bool>(v.cast<bool>()));
    } else if (py::isinstance<py::int_>(v)) {
        insert(toml::value<std::int64_t>(v.cast<std::int64_t>()));
    } else if (py::isinstance<py::float_>(v)) {
        insert(toml::value<double>(v.cast<double>()));
    } else if (py::isinstance<py::str>(v)) {
        insert(toml::value<std::string>(v.cast<std::string>()));
    } else if (py::isinstance<py::dict>(v)) {
        insert(to_table(v.cast<py::dict>(), where));
    } else if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) {
        insert(to_array(v, where));
    } else if (py::hasattr(v, "tolist")) { // NumPy arrays and scalars
        insert_value(v.attr("tolist")(), where, insert);
    } else {
        throw py::type_error(where + ": a bool, int, float, str, list or dict is expected, not " +
                             std::string(py::str(v.get_type().attr("__name__"))));
    }
}

toml::array to_array(const py::handle& list, const std::string& where) {
    toml::array a;
    std::size_t i = 0;
    for (const py::handle item : list) {
        insert_value(item, where + "[" + std::to_string(i++) + "]",
                     [&](auto&& node) { a.push_back(std::move(node)); });
    }
    return a;
}

toml::table to_table(const py::dict& dict, const std::string& where) {
    toml::table t;
    for (const auto& [k, v] : dict) {
        if (!py::isinstance<py::str>(k)) {
            throw py::type_error(where + ": keys must be strings");
        }
        const std::string key = k.cast<std::string>();
        insert_value(v, where.empty() ? key : where + "." + key,
                     [&](auto&& node) { t.insert_or_assign(key, std::move(node)); });
    }
    return t;
}

std::string scene_text(const py::dict& scene) {
    std::ostringstream out;
    out << to_table(scene, "") << "\n";
    return out.str();
}

std::string value_text(const py::handle& value) {
    toml::table holder;
    insert_value(value, "value",
                 [&](auto&& node) { holder.insert_or_assign("v", std::move(node)); });
    return ifsim::io::toml_value_text(*holder.get("v"));
}

int run_cli(const std::vector<std::string>& args) {
    std::vector<std::string> all = {"ifsim"};
    all.insert(all.end(), args.begin(), args.end());
    std::vector<const char*> argv;
    for (const std::string& a : all) {
        argv.push_back(a.c_str());
    }
    const py::gil_scoped_release free_python; // a long run does not hold other Python threads
    return ifsim::io::run_cli(static_cast<int>(argv.size()), argv.data());
}

} // namespace

PYBIND11_MODULE(_ifsim, m) {
    m.doc() = "The compiled part of ifsim's Python module (use `import ifsim`).";
    m.def("run_cli", &run_cli, py::arg("args"),
          "Runs `ifsim ARGS...` in this process and returns its exit code.");
    m.def("scene_text", &scene_text, py::arg("scene"), "A scene given as a dict, as TOML text.");
    m.def("value_text", &value_text, py::arg("value"),
          "A Python value as the TOML text of a --set value.");
    m.attr("version") = ifsim::io::build_version();
    m.attr("revision") = ifsim::io::build_revision();
}
