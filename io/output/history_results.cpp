#include "io/output/history_results.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace ifsim::io {

namespace {

std::vector<std::string> split_csv_line(const std::string& line) {
    std::vector<std::string> fields;
    std::string field;
    for (const char c : line) {
        if (c == ',') {
            fields.push_back(field);
            field.clear();
        } else if (c != '\r') {
            field += c;
        }
    }
    fields.push_back(field);
    return fields;
}

double field_value(const std::string& text) {
    if (text.empty()) {
        return std::numeric_limits<double>::quiet_NaN();
    }
    char* end = nullptr;
    const double x = std::strtod(text.c_str(), &end);
    return end == text.c_str() ? std::numeric_limits<double>::quiet_NaN() : x;
}

// Running last value and maximum of one derived quantity.
struct Tracker {
    double last = std::numeric_limits<double>::quiet_NaN();
    double peak = -std::numeric_limits<double>::infinity();
    void add(double x) {
        if (std::isfinite(x)) {
            last = x;
            peak = std::max(peak, x);
        }
    }
    bool seen() const { return std::isfinite(last); }
};

} // namespace

nlohmann::ordered_json history_results(const std::filesystem::path& history_csv) {
    nlohmann::ordered_json results = nlohmann::ordered_json::object();
    std::ifstream in(history_csv);
    std::string line;
    if (!in || !std::getline(in, line)) {
        return results;
    }
    const std::vector<std::string> header = split_csv_line(line);
    const auto column = [&](const char* name) -> std::optional<std::size_t> {
        for (std::size_t i = 0; i < header.size(); ++i) {
            if (header[i] == name) {
                return i;
            }
        }
        return std::nullopt;
    };
    const auto t_t1 = column("t_t1"), t_t2 = column("t_t2"), t_n = column("t_n");
    const auto u_t1 = column("u_t1"), u_n = column("u_n");
    const auto e = column("e"), e_interface = column("e_interface");
    const char* const stress_names[6] = {"s11", "s22", "s33", "s12", "s13", "s23"};
    std::optional<std::size_t> stress[6];
    bool has_stress = true;
    for (int k = 0; k < 6; ++k) {
        stress[k] = column(stress_names[k]);
        has_stress = has_stress && stress[k].has_value();
    }
    Tracker shear, shear_t1, normal, slip, dilation, void_ratio, band_void_ratio, mean, q;
    long rows = 0;
    while (std::getline(in, line)) {
        if (line.empty()) {
            continue;
        }
        const std::vector<std::string> f = split_csv_line(line);
        if (f.size() != header.size()) {
            continue; // a torn last row of a killed run
        }
        ++rows;
        const auto at = [&](const std::optional<std::size_t>& c) {
            return c ? field_value(f[*c]) : std::numeric_limits<double>::quiet_NaN();
        };
        if (t_t1) {
            const double a = at(t_t1);
            const double b = t_t2 ? at(t_t2) : 0.0;
            shear.add(std::hypot(a, std::isfinite(b) ? b : 0.0));
            shear_t1.add(a);
        }
        normal.add(at(t_n));
        slip.add(at(u_t1));
        dilation.add(at(u_n));
        void_ratio.add(at(e));
        band_void_ratio.add(at(e_interface));
        if (has_stress) {
            double s[6];
            for (int k = 0; k < 6; ++k) {
                s[k] = at(stress[k]);
            }
            const double p = (s[0] + s[1] + s[2]) / 3.0;
            const double d0 = s[0] - p, d1 = s[1] - p, d2 = s[2] - p;
            const double dev2 =
                d0 * d0 + d1 * d1 + d2 * d2 + 2.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]);
            mean.add(p);
            q.add(std::sqrt(1.5 * dev2));
        }
    }
    if (rows == 0) {
        return results;
    }
    results["rows"] = rows;
    const auto put = [&](const char* name, double x) {
        if (std::isfinite(x)) {
            results[name] = x;
        }
    };
    if (shear.seen()) {
        put("peak_shear_stress", shear.peak);
        put("final_shear_stress", shear_t1.last);
    }
    put("final_normal_stress", normal.last);
    put("final_shear_displacement", slip.last);
    put("final_normal_displacement", dilation.last);
    if (q.seen()) {
        put("final_mean_stress", mean.last);
        put("peak_q", q.peak);
        put("final_q", q.last);
    }
    put("final_void_ratio", void_ratio.last);
    put("final_interface_void_ratio", band_void_ratio.last);
    return results;
}

} // namespace ifsim::io
