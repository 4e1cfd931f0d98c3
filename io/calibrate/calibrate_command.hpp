#pragma once
// `ifsim calibrate CAL.toml --out DIR`: fits chosen keys of a scene (calibration_file.hpp) to a
// measured curve by least squares — Levenberg-Marquardt of Ceres Solver within the keys'
// bounds, the Jacobian by forward differences whose runs go at once over the cores (and MPI
// ranks). Writes DIR/calibration.json (fitted values, cost, residuals, Ceres' report),
// DIR/fit.csv (data against the fitted run), DIR/evaluations.csv (every point run) and the runs
// in DIR/runs/<id>. Returns the process exit code: 0 fitted (converged or out of iterations, as
// calibration.json says), 2 bad input, 3 no run at the initial values reached the data's end,
// 1 DIR not writable, 128+N stopped by signal N.

#include "io/sweep/sweep_command.hpp"

namespace ifsim::io {

struct CalibrateOptions {
    std::string file;
    SweepOptions runs; // out, jobs, threads per run, scalar, quiet, executable
};

int calibrate_command(const CalibrateOptions& options);

} // namespace ifsim::io
