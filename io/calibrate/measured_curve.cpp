#include "io/calibrate/measured_curve.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "io/scene/scene_error.hpp"

namespace ifsim::io {

namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

std::vector<std::string> split(const std::string& line) {
    std::vector<std::string> fields;
    std::string f;
    for (const char c : line) {
        if (c == ',') {
            fields.push_back(f);
            f.clear();
        } else if (c != '\r' && c != ' ' && c != '"') {
            f += c;
        }
    }
    fields.push_back(f);
    return fields;
}

struct Table {
    std::vector<std::string> header;
    std::vector<std::vector<std::string>> rows;
};

Table read_csv(const std::filesystem::path& path) {
    std::ifstream in(path);
    if (!in) {
        throw std::runtime_error(fmt::format("cannot read {}", path.string()));
    }
    Table t;
    std::string line;
    if (std::getline(in, line)) {
        t.header = split(line);
    }
    while (std::getline(in, line)) {
        if (!line.empty() && line != "\r") {
            t.rows.push_back(split(line));
        }
    }
    return t;
}

// Path length of the tangential displacement, from u_t = 0.
std::vector<double> path_of(const std::vector<double>& u_t) {
    std::vector<double> s(u_t.size());
    double acc = 0.0, last = 0.0;
    for (std::size_t i = 0; i < u_t.size(); ++i) {
        acc += std::abs(u_t[i] - last);
        last = u_t[i];
        s[i] = acc;
    }
    return s;
}

double interpolate(const std::vector<double>& s, const std::vector<double>& y, double at) {
    if (s.empty() || at > s.back() * (1.0 + 1e-12) + 1e-15) {
        return nan;
    }
    const auto hi = std::upper_bound(s.begin(), s.end(), at);
    if (hi == s.begin()) {
        return y.front();
    }
    if (hi == s.end()) {
        return y.back();
    }
    const std::size_t j = static_cast<std::size_t>(hi - s.begin());
    const double s0 = s[j - 1], s1 = s[j];
    const double w = s1 > s0 ? (at - s0) / (s1 - s0) : 1.0;
    return (1.0 - w) * y[j - 1] + w * y[j];
}

} // namespace

CurvePoints read_measured_curve(const std::filesystem::path& csv, const std::string& u_t,
                                const std::string& t_t, const std::string& u_n) {
    const std::string file = csv.string();
    Table t;
    try {
        t = read_csv(csv);
    } catch (const std::exception& e) {
        throw SceneError(file, "", e.what());
    }
    const auto column = [&](const std::string& name, bool required) -> long {
        const auto it = std::find(t.header.begin(), t.header.end(), name);
        if (it == t.header.end()) {
            if (required) {
                throw SceneError(file, name,
                                 fmt::format("a column named {} in the header line (it has: {})",
                                             name, fmt::join(t.header, ", ")));
            }
            return -1;
        }
        return it - t.header.begin();
    };
    const long cu = column(u_t, true), ct = column(t_t, true), cn = column(u_n, false);
    CurvePoints c;
    for (std::size_t r = 0; r < t.rows.size(); ++r) {
        const auto value = [&](long col, const std::string& name) {
            const std::vector<std::string>& row = t.rows[r];
            const std::string text = static_cast<std::size_t>(col) < row.size() ? row[col] : "";
            char* end = nullptr;
            const double x = std::strtod(text.c_str(), &end);
            if (text.empty() || *end != '\0' || !std::isfinite(x)) {
                throw SceneError(
                    file, name,
                    fmt::format("a finite number in data row {} (got \"{}\")", r + 1, text),
                    static_cast<int>(r + 2));
            }
            return x;
        };
        c.u_t.push_back(value(cu, u_t));
        c.t_t.push_back(value(ct, t_t));
        if (cn >= 0) {
            c.u_n.push_back(value(cn, u_n));
        }
    }
    if (c.u_t.size() < 2) {
        throw SceneError(file, u_t, "at least 2 data rows");
    }
    c.path = path_of(c.u_t);
    return c;
}

CurvePoints read_run_curve(const std::filesystem::path& history_csv) {
    const Table t = read_csv(history_csv);
    const auto column = [&](const char* name) {
        const auto it = std::find(t.header.begin(), t.header.end(), name);
        if (it == t.header.end()) {
            throw std::runtime_error(
                fmt::format("{} has no column {}", history_csv.string(), name));
        }
        return static_cast<std::size_t>(it - t.header.begin());
    };
    const std::size_t cu = column("u_t1"), ct = column("t_t1"), cn = column("u_n");
    CurvePoints c;
    for (const auto& row : t.rows) {
        if (row.size() != t.header.size()) {
            continue; // a torn last row
        }
        c.u_t.push_back(std::strtod(row[cu].c_str(), nullptr));
        c.t_t.push_back(std::strtod(row[ct].c_str(), nullptr));
        c.u_n.push_back(std::strtod(row[cn].c_str(), nullptr));
    }
    c.path = path_of(c.u_t);
    return c;
}

CurveScales curve_scales(const CurvePoints& data) {
    CurveScales s;
    const auto largest = [](const std::vector<double>& v) {
        double m = 0.0;
        for (const double x : v) {
            m = std::max(m, std::abs(x));
        }
        return m;
    };
    s.t_t = std::max(largest(data.t_t), 1e-12);
    s.u_n = std::max(largest(data.u_n), 1e-15);
    return s;
}

CurvePoints run_at_data_points(const CurvePoints& data, const CurvePoints& run) {
    CurvePoints at;
    at.path = data.path;
    at.u_t = data.u_t;
    for (const double s : data.path) {
        at.t_t.push_back(interpolate(run.path, run.t_t, s));
        at.u_n.push_back(interpolate(run.path, run.u_n, s));
    }
    return at;
}

std::optional<std::vector<double>> curve_residuals(const CurvePoints& data, const CurvePoints& run,
                                                   const CurveScales& scales, double weight_u_n) {
    const CurvePoints at = run_at_data_points(data, run);
    std::vector<double> r;
    for (std::size_t i = 0; i < data.t_t.size(); ++i) {
        r.push_back((at.t_t[i] - data.t_t[i]) / scales.t_t);
    }
    if (!data.u_n.empty() && weight_u_n > 0.0) {
        for (std::size_t i = 0; i < data.u_n.size(); ++i) {
            r.push_back(weight_u_n * (at.u_n[i] - data.u_n[i]) / scales.u_n);
        }
    }
    for (const double x : r) {
        if (!std::isfinite(x)) {
            return std::nullopt;
        }
    }
    return r;
}

} // namespace ifsim::io
