#pragma once
// A measured interface shear curve and a run's curve compared point by point. Both are
// parametrised by the path length of the tangential displacement, s = |u_t,0| + sum |du_t|
// (the data start from u_t = 0), so monotonic and cyclic tests are compared alike: the run's
// t_t1 and u_n are interpolated linearly in s at each measured point.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace ifsim::io {

struct CurvePoints {
    std::vector<double> path; // s (m), non-decreasing
    std::vector<double> u_t;  // m
    std::vector<double> t_t;  // kPa
    std::vector<double> u_n;  // m (empty when the data have none)
};

// Reads the measured curve (CSV with a header; the named columns, others ignored). Throws
// SceneError naming the file, the column and what was expected (a missing column, a field that
// is no number, fewer than 2 rows).
CurvePoints read_measured_curve(const std::filesystem::path& csv, const std::string& u_t,
                                const std::string& t_t, const std::string& u_n);

// A run's curve from its history.csv (u_t1, t_t1, u_n). Throws std::runtime_error when the
// file or its columns are missing.
CurvePoints read_run_curve(const std::filesystem::path& history_csv);

struct CurveScales {
    double t_t = 1.0; // kPa: the largest |t_t| of the data
    double u_n = 1.0; // m: the largest |u_n| of the data
};
CurveScales curve_scales(const CurvePoints& data);

// Residuals (run - data) / scale at every data point: the t_t ones, then, when the data have
// u_n and weight_u_n > 0, weight_u_n times the u_n ones. nullopt when the run's path does not
// reach the data's end (a run that failed on the way).
std::optional<std::vector<double>> curve_residuals(const CurvePoints& data, const CurvePoints& run,
                                                   const CurveScales& scales, double weight_u_n);

// The run's t_t and u_n at the data's path lengths (NaN beyond the run's end).
CurvePoints run_at_data_points(const CurvePoints& data, const CurvePoints& run);

} // namespace ifsim::io
