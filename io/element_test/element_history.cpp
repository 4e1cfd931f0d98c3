#include "io/element_test/element_history.hpp"

#include <stdexcept>

#include <fmt/format.h>

#include "io/element_test/element_test_scene.hpp"

namespace ifsim::io {

namespace {

void add_six(std::vector<std::string>& cols, const char* prefix) {
    for (const char* s : voigt_suffix) {
        cols.push_back(fmt::format("{}{}", prefix, s));
    }
}

} // namespace

std::vector<std::string> element_history_columns(const MaterialChoice& material) {
    std::vector<std::string> cols = {"step", "stage"};
    add_six(cols, "eps");
    add_six(cols, "s");
    cols.emplace_back("e");
    for (std::string_view prefix : history_prefixes(material)) { // engine/model_registry.hpp
        add_six(cols, std::string(prefix).c_str());
    }
    if (static_cast<int>(cols.size()) != 2 + 6 + state_size(material)) {
        throw std::logic_error(fmt::format("history columns of model {} do not match its state "
                                           "size {}",
                                           model_name(material), state_size(material)));
    }
    return cols;
}

void write_element_row(HistoryWriter& out, const ElementRow& row) {
    out.integer(row.step);
    out.integer(row.stage);
    for (double v : row.strain) {
        out.real(v);
    }
    for (double v : row.state) {
        out.real(v);
    }
    out.end_row();
}

} // namespace ifsim::io
