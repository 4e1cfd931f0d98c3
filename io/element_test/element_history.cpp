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
    if (static_cast<int>(cols.size()) != 2 + 6 + reported_state_size(material)) {
        throw std::logic_error(fmt::format("history columns of model {} do not match its "
                                           "reported state size {}",
                                           model_name(material), reported_state_size(material)));
    }
    return cols;
}

void write_element_row(HistoryWriter& out, const ElementRow& row, int reported_state) {
    out.integer(row.step);
    out.integer(row.stage);
    for (double v : row.strain) {
        out.real(v);
    }
    for (int k = 0; k < reported_state; ++k) {
        out.real(row.state[static_cast<std::size_t>(k)]);
    }
    out.end_row();
}

} // namespace ifsim::io
