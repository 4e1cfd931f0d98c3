#pragma once
// A calibration file (`ifsim calibrate CAL.toml`): which keys of a scene to fit, within which
// bounds and from where, to which measured curve. Example:
//
//   scene = "../scenes/simple-shear-cnl-stutz.toml"   # relative to this file
//   data = "measured.csv"                             # columns u_t (m), t_t (kPa) [, u_n (m)]
//   [parameters]
//   "interface.roughness" = { initial = 0.8, bounds = [0.5, 0.95] }
//   "interface.shear_band_thickness" = { initial = 0.002, bounds = [0.001, 0.006] }
//   [set]                                             # optional: overrides of every run
//   "interface.subincrement" = "adaptive"
//   [fit]                                             # optional
//   weight_u_n = 1.0        # weight of the normal displacement residuals (0 = t_t only)
//   max_iterations = 30     # Levenberg-Marquardt iterations
//   step = 0.01             # forward-difference step, a fraction of each parameter's range
//   [columns]                                         # optional: the data file's column names
//   u_t = "u_t"
//   t_t = "t_t"
//   u_n = "u_n"

#include <filesystem>
#include <string>
#include <vector>

namespace ifsim::io {

struct FittedParameter {
    std::string key; // a --set key
    double initial = 0.0;
    double lower = 0.0;
    double upper = 0.0;
};

struct CalibrationFile {
    std::filesystem::path file;
    std::string scene;                // as written
    std::filesystem::path scene_path; // resolved against the file's folder
    std::filesystem::path data_path;
    std::vector<FittedParameter> parameters; // in the order of the file
    std::vector<std::string> fixed;          // KEY=VALUE given to every run
    double weight_u_n = 1.0;
    int max_iterations = 30;
    double step = 0.01;
    std::string column_u_t = "u_t";
    std::string column_t_t = "t_t";
    std::string column_u_n = "u_n";
    std::string description;
};

// Reads and checks a calibration file. Throws SceneError naming the file, the key and what was
// expected (missing files, bounds not around the initial value, an empty [parameters], ...).
CalibrationFile read_calibration_file(const std::filesystem::path& file);

} // namespace ifsim::io
