#pragma once
// The runs of a calibration: each set of parameter values is one `ifsim run` of the scene with
// those values as overrides, in DIR/runs/<id> like a sweep member (the same id for the same
// values, so a point evaluated again, or in an earlier calibration, is read back instead of
// run). A batch of points (a Jacobian's columns) runs at once over the cores and MPI ranks.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "io/calibrate/calibration_file.hpp"
#include "io/calibrate/measured_curve.hpp"
#include "io/sweep/remote_workers.hpp"
#include "io/sweep/sweep_coordinator.hpp"
#include "io/sweep/sweep_plan.hpp"

namespace ifsim::io {

// One evaluated point, for evaluations.csv.
struct Evaluation {
    std::size_t batch = 0;
    std::vector<double> values;
    std::string id;
    bool ok = false;     // the run finished and reached the data's end
    std::string reason;  // why not
    double cost = 0.0;   // 1/2 sum of squared residuals
    bool reused = false; // read back from an earlier run
};

class CurveEvaluator {
public:
    CurveEvaluator(const CalibrationFile& cal, const CurvePoints& data, const SweepOptions& runs,
                   const SweepLayout& layout, RemoteWorkers* remote);

    // Runs every point (values of the fitted keys, in their units) and returns the residuals of
    // each (nullopt: the run failed or stopped short). After a stop signal nothing more runs
    // and every point is nullopt (interrupted() says which signal).
    std::vector<std::optional<std::vector<double>>>
    evaluate(const std::vector<std::vector<double>>& points);

    // The run folder of a point (evaluated before).
    std::filesystem::path run_dir(const std::vector<double>& values) const;

    const std::vector<Evaluation>& evaluations() const { return evaluations_; }
    int interrupted() const { return interrupted_; }
    const CurveScales& scales() const { return scales_; }
    std::size_t residual_count() const;

private:
    std::vector<std::string> sets_of(const std::vector<double>& values) const;

    const CalibrationFile& cal_;
    const CurvePoints& data_;
    CurveScales scales_;
    SweepOptions runs_;
    SweepLayout layout_;
    RemoteWorkers* remote_;
    SweepPlan plan_;
    std::string scene_text_;
    std::vector<Evaluation> evaluations_;
    std::size_t batches_ = 0;
    int interrupted_ = 0;
};

} // namespace ifsim::io
