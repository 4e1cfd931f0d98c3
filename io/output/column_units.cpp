#include "io/output/column_units.hpp"

#include <stdexcept>

#include <fmt/format.h>

namespace ifsim::io {
namespace {

struct Rule {
    std::string_view prefix; // a column equal to it, or (six_components) it plus 11..23
    bool six_components;
    ColumnDescription d;
};

const char* const voigt[] = {"11", "22", "33", "12", "13", "23"};

std::optional<ColumnDescription> match(const std::vector<Rule>& rules, std::string_view column) {
    for (const Rule& r : rules) {
        if (!r.six_components && column == r.prefix) {
            return r.d;
        }
        if (r.six_components && column.starts_with(r.prefix)) {
            const std::string_view rest = column.substr(r.prefix.size());
            for (const char* c : voigt) {
                if (rest == c) {
                    return ColumnDescription{r.d.unit, fmt::format("{} ({})", r.d.meaning, c)};
                }
            }
        }
    }
    return std::nullopt;
}

const std::vector<Rule>& element_rules() {
    static const std::vector<Rule> rules = {
        {"step", false, {"-", "step number, 0 = initial state"}},
        {"stage", false, {"-", "stage number, 0 = initial state"}},
        {"eps", true, {"-", "total strain since step 0, tensor component"}},
        {"s", true, {"kPa", "stress"}},
        {"e", false, {"-", "void ratio"}},
        {"h", true, {"-", "intergranular strain (hypoplasticity)"}},
        {"ain", true, {"-", "back-stress ratio at the last load reversal (Sanisand)"}},
        {"a", true, {"-", "back-stress ratio alpha (Sanisand)"}},
        {"z", true, {"-", "fabric tensor (Sanisand)"}},
    };
    return rules;
}

const std::vector<Rule>& interface_rules() {
    static const std::vector<Rule> rules = {
        {"step", false, {"-", "step number, 0 = initial state"}},
        {"stage", false, {"-", "stage number, 0 = initial state"}},
        {"u_t1", false, {"m", "plate tangential displacement along t1"}},
        {"u_t2", false, {"m", "plate tangential displacement along t2"}},
        {"u_n", false, {"m", "plate normal displacement, dilation positive"}},
        {"t_n", false, {"kPa", "normal contact stress t_N"}},
        {"t_t1", false, {"kPa", "shear stress along t1"}},
        {"t_t2", false, {"kPa", "shear stress along t2"}},
        {"s_n", false, {"kPa", "interface normal stress sigma_N (Eq. 17)"}},
        {"s_p1", false, {"kPa", "interface in-plane stress sigma_p1"}},
        {"s_p2", false, {"kPa", "interface in-plane stress sigma_p2"}},
        {"eps_n", false, {"-", "interface normal strain epsilon_N"}},
        {"eps_p1", false, {"-", "interface in-plane strain epsilon_p1"}},
        {"eps_p2", false, {"-", "interface in-plane strain epsilon_p2"}},
        {"gamma1", false, {"-", "interface engineering shear strain along t1"}},
        {"gamma2", false, {"-", "interface engineering shear strain along t2"}},
        {"band_thickness", false, {"m", "shear band thickness d_s (Eq. 26)"}},
        {"sample_s11", false, {"kPa", "sample stress 11"}},
        {"sample_s22", false, {"kPa", "sample stress 22"}},
        {"sample_s33", false, {"kPa", "sample stress 33"}},
        {"sample_s12", false, {"kPa", "sample shear stress 12"}},
        {"sample_s13", false, {"kPa", "sample shear stress 13"}},
        {"e_interface", false, {"-", "void ratio of the interface zone"}},
        {"e_sample", false, {"-", "void ratio of the sample"}},
        {"slip1", false, {"m", "accumulated interface slip along t1"}},
        {"slip2", false, {"m", "accumulated interface slip along t2"}},
        {"newton_iterations", false, {"-", "Newton corrections of the step"}},
    };
    return rules;
}

// One Algorithm 1 call: row 0 the committed state, row 1 the call's result (when it succeeded).
const std::vector<Rule>& interface_point_rules() {
    static const std::vector<Rule> rules = {
        {"step", false, {"-", "0 = the point's state before the call, 1 = after it"}},
        {"t_n", false, {"kPa", "normal traction t_N (row 0: the band's sigma_N)"}},
        {"t_t1", false, {"kPa", "shear traction along the local t1"}},
        {"t_t2", false, {"kPa", "shear traction along the local t2"}},
    };
    return rules;
}

const std::vector<Rule>& boundary_value_rules() {
    static const std::vector<Rule> rules = {
        {"increment", false, {"-", "converged increment, 0 = initial state"}},
        {"stage", false, {"-", "stage number, 0 = initial state"}},
        {"time", false, {"-", "completed stages plus pseudo-time in the stage"}},
        {"newton_iterations", false, {"-", "Newton corrections of the increment"}},
        {"u_t1",
         false,
         {"m", "relative displacement along the pair's t1 (shear_direction; x without "
               "contact): output.plate minus output.soil_top, or per pair master minus slave"}},
        {"u_t2", false, {"m", "the same along t2 = t1 x n (y without contact; 3D)"}},
        {"u_n",
         false,
         {"m", "relative displacement along the slave's outward normal n: soil_top minus plate "
               "along -n (dilation positive; vertical without contact), or per pair master "
               "minus slave along n (opening positive)"}},
        {"t_n", false, {"kPa", "mean normal traction on the soil"}},
        {"t_t1",
         false,
         {"kPa", "mean shear traction on the soil along the pair's t1 (x without contact)"}},
        {"t_t2",
         false,
         {"kPa", "mean shear traction on the soil along t2 (y without contact; 3D)"}},
        {"F_n", false, {"kN", "normal contact force on the soil (per m in 2D)"}},
        {"F_t1", false, {"kN", "shear contact force on the soil along t1 (per m in 2D)"}},
        {"F_t2", false, {"kN", "shear contact force on the soil along t2 (3D)"}},
        {"cuts", false, {"-", "halvings of the nominal step"}},
        {"residual", false, {"-", "last relative residual of the increment"}},
        {"closed_points", false, {"-", "contact points in compression"}},
        {"s_p1", false, {"kPa", "mean interface in-plane stress sigma_p1"}},
        {"s_p2", false, {"kPa", "mean interface in-plane stress sigma_p2"}},
        {"eps_n", false, {"-", "mean interface normal strain epsilon_N"}},
        {"band_thickness", false, {"m", "mean shear band thickness d_s (Eq. 26)"}},
        {"e_interface", false, {"-", "mean void ratio of the interface zone"}},
    };
    return rules;
}

} // namespace

std::optional<ColumnDescription> describe_column(std::string_view kind, std::string_view column) {
    if (kind == "element-test") {
        return match(element_rules(), column);
    }
    if (kind == "interface-test") {
        return match(interface_rules(), column);
    }
    if (kind == "interface-point") {
        const auto own = match(interface_point_rules(), column);
        return own ? own : match(interface_rules(), column);
    }
    if (kind == "boundary-value") {
        // <pair>.t_n, ...: a pair's own means, as the main columns.
        const auto dot = column.rfind('.');
        if (dot != std::string_view::npos) {
            auto d = match(boundary_value_rules(), column.substr(dot + 1));
            if (d) {
                d->meaning = fmt::format("{} (pair {})", d->meaning, column.substr(0, dot));
            }
            return d;
        }
        return match(boundary_value_rules(), column);
    }
    return std::nullopt;
}

nlohmann::ordered_json describe_columns(std::string_view kind,
                                        const std::vector<std::string>& columns,
                                        const std::vector<NamedColumn>& named) {
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    for (const std::string& c : columns) {
        std::optional<ColumnDescription> d;
        for (const auto& [name, description] : named) {
            if (name == c) {
                d = description;
                break;
            }
        }
        if (!d) {
            d = describe_column(kind, c);
        }
        if (!d) {
            throw std::logic_error(
                fmt::format("history column '{}' of a {} run has no unit", c, kind));
        }
        out.push_back({{"name", c}, {"unit", d->unit}, {"meaning", d->meaning}});
    }
    return out;
}

} // namespace ifsim::io
