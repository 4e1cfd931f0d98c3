#include "io/scene/resume_overrides.hpp"

#include <algorithm>
#include <array>
#include <cctype>

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace ifsim::io {

namespace {

constexpr std::array<std::string_view, 18> contact_keys = {
    "tolerance",          "max_subincrement",    "work_newton_iterations", "work_model_substeps",
    "jacobian",           "perturbation",        "model_tolerance",        "newton_jacobian",
    "newton_fallback",    "newton_switch_ratio", "newton_switch_jacobian", "jacobian_tolerance",
    "polish_iterations",  "adaptive_partition",  "defer_jacobian",         "slip_viscosity",
    "slip_viscosity_use", "newton_line_search"};

bool all_digits(std::string_view s) {
    return !s.empty() &&
           std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c) != 0; });
}

} // namespace

std::span<const std::string_view> resumable_contact_keys() {
    return contact_keys;
}

std::string resume_override_refusal(std::string_view assignment) {
    const std::size_t eq = assignment.find('=');
    std::string_view key = assignment.substr(0, eq);
    while (!key.empty() && key.back() == ' ') {
        key.remove_suffix(1);
    }
    const auto refuse = [&] {
        return fmt::format(
            "--set {}: a resumed run can change only how the equations are solved: keys under "
            "solver., and contact.N.KEY or interface.KEY for KEY one of {}; the checkpoint's "
            "state was made with the rest of the scene",
            key, fmt::join(contact_keys, ", "));
    };
    if (eq == std::string_view::npos || key.empty()) {
        return fmt::format("--set {}: expected KEY=VALUE", assignment);
    }
    if (key.starts_with("solver.") && key.size() > 7) {
        return {};
    }
    std::string_view last;
    if (key.starts_with("interface.")) {
        last = key.substr(10);
    } else if (key.starts_with("contact.")) {
        const std::string_view rest = key.substr(8);
        const std::size_t dot = rest.find('.');
        if (dot == std::string_view::npos || !all_digits(rest.substr(0, dot))) {
            return refuse();
        }
        last = rest.substr(dot + 1);
    } else {
        return refuse();
    }
    if (std::find(contact_keys.begin(), contact_keys.end(), last) == contact_keys.end()) {
        return refuse();
    }
    return {};
}

} // namespace ifsim::io
