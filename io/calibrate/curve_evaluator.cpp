#include "io/calibrate/curve_evaluator.hpp"

#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "io/output/stop_signal.hpp"
#include "io/sweep/sweep_file.hpp"
#include "io/sweep/sweep_members.hpp"

namespace ifsim::io {

namespace fs = std::filesystem;

CurveEvaluator::CurveEvaluator(const CalibrationFile& cal, const CurvePoints& data,
                               const SweepOptions& runs, const SweepLayout& layout,
                               RemoteWorkers* remote)
    : cal_(cal), data_(data), scales_(curve_scales(data)), runs_(runs), layout_(layout),
      remote_(remote) {
    plan_.file.file = cal.file;
    plan_.file.scenes = {cal.scene};
    plan_.file.paths = {cal.scene_path};
    plan_.file.fixed = cal.fixed;
    plan_.out = runs.out;
    std::ifstream in(cal.scene_path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    scene_text_ = text.str();
}

std::size_t CurveEvaluator::residual_count() const {
    const bool with_u_n = !data_.u_n.empty() && cal_.weight_u_n > 0.0;
    return data_.t_t.size() * (with_u_n ? 2 : 1);
}

std::vector<std::string> CurveEvaluator::sets_of(const std::vector<double>& values) const {
    std::vector<std::string> sets = cal_.fixed;
    for (std::size_t k = 0; k < values.size(); ++k) {
        sets.push_back(cal_.parameters[k].key + "=" +
                       toml_value_text(toml::value<double>(values[k])));
    }
    return sets;
}

fs::path CurveEvaluator::run_dir(const std::vector<double>& values) const {
    return runs_.out / fs::path("runs") / run_id(scene_text_, sets_of(values));
}

std::vector<std::optional<std::vector<double>>>
CurveEvaluator::evaluate(const std::vector<std::vector<double>>& points) {
    if (interrupted_ != 0) {
        return std::vector<std::optional<std::vector<double>>>(points.size());
    }
    ++batches_;
    // One plan member per point; a point whose folder holds an ok run is read back.
    const std::size_t first = plan_.members.size();
    std::vector<std::size_t> pending;
    std::vector<bool> reused(points.size(), false);
    for (std::size_t p = 0; p < points.size(); ++p) {
        SweepMember m;
        m.index = plan_.members.size() + 1;
        m.sets = sets_of(points[p]);
        m.id = run_id(scene_text_, m.sets);
        plan_.members.push_back(m);
        std::optional<RunRecord> earlier = read_run_record(plan_.run_dir(m));
        const bool queued = [&] {
            for (const std::size_t i : pending) {
                if (plan_.members[i].id == m.id) {
                    return true;
                }
            }
            return false;
        }();
        if (reusable(earlier, runs_.scalar)) {
            reused[p] = true;
            plan_.records.push_back(std::move(earlier));
        } else {
            plan_.records.emplace_back();
            if (!queued) {
                pending.push_back(plan_.members.size() - 1);
            }
        }
    }
    SweepOptions quiet = runs_;
    quiet.quiet = true;
    if ((interrupted_ = run_members(plan_, pending, layout_, quiet, remote_)) != 0) {
        return std::vector<std::optional<std::vector<double>>>(points.size());
    }
    std::vector<std::optional<std::vector<double>>> out;
    for (std::size_t p = 0; p < points.size(); ++p) {
        const std::size_t i = first + p;
        const SweepMember& m = plan_.members[i];
        Evaluation e{batches_, points[p], m.id, false, "", 0.0, reused[p]};
        std::optional<std::vector<double>> r;
        const std::optional<RunRecord>& record = plan_.records[i];
        if (!record || !record->ok) {
            e.reason = record ? record->reason : "not run";
        } else {
            try {
                r = curve_residuals(data_, read_run_curve(plan_.run_dir(m) / "history.csv"),
                                    scales_, cal_.weight_u_n);
                if (!r) {
                    e.reason = "the run's path ends before the data's";
                }
            } catch (const std::exception& ex) {
                e.reason = ex.what();
            }
        }
        if (r) {
            e.ok = true;
            for (const double x : *r) {
                e.cost += 0.5 * x * x;
            }
        }
        evaluations_.push_back(e);
        out.push_back(std::move(r));
    }
    return out;
}

} // namespace ifsim::io
