// `--iteration-log`: DIR/iterations.csv has one row per Newton iteration of every increment,
// its counters are differences that add up to the run's totals in summary.json, each
// increment's rows end at the residual history.csv accepted, the replay of the costliest
// Algorithm 1 call (DIR/costliest-call.toml) costs alone what the run counted for it, and the
// option is refused for scene kinds without Newton iterations.

#include <cstddef>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "io/boundary_value/iteration_log.hpp"
#include "io/cli/exit_codes.hpp"
#include "io/replay/interface_replay.hpp"
#include "tests/io/boundary_value_test_support.hpp"
#include "tests/io/scene_test_support.hpp"

namespace ifsim::io {
namespace {

namespace fs = std::filesystem;

// iterations.csv as rows of name -> number.
std::vector<std::map<std::string, double>> read_log(const fs::path& dir) {
    std::istringstream in(test::read_text(dir / IterationLog::file_name));
    std::string line;
    std::getline(in, line);
    std::vector<std::string> names;
    std::istringstream hs(line);
    for (std::string n; std::getline(hs, n, ',');) {
        names.push_back(n);
    }
    std::vector<std::map<std::string, double>> rows;
    while (std::getline(in, line)) {
        std::istringstream ls(line);
        std::map<std::string, double> row;
        std::size_t k = 0;
        for (std::string v; std::getline(ls, v, ','); ++k) {
            row[names.at(k)] = std::stod(v);
        }
        EXPECT_EQ(k, names.size()) << line;
        rows.push_back(row);
    }
    return rows;
}

double column_sum(const std::vector<std::map<std::string, double>>& rows, const char* name) {
    double sum = 0.0;
    for (const auto& r : rows) {
        sum += r.at(name);
    }
    return sum;
}

TEST(IterationLog, RowsAddUpToTheRunAndEndAtTheAcceptedResidual) {
    const fs::path dir = test::fresh_dir("iteration-log");
    const auto r = test::run_cli_captured(
        {"run", "scenes/fe-simple-shear-cnl-2d.toml", "--out", dir.string(), "--threads", "1",
         "--iteration-log", "--set", "stage.2.steps=5", "--set",
         "stage.2.displacement.1.change=0.00015", "--set", "solver.reuse_factorisation=true"});
    ASSERT_EQ(r.code, 0) << r.err;
    const auto rows = read_log(dir);
    const test::History h = test::read_history(dir);
    const nlohmann::json s = test::summary(dir);
    ASSERT_EQ(h.rows.size(), 7u); // row 0, consolidation, 5 shear increments

    // Differences since the row before: their sums are the run's totals.
    const nlohmann::json& c = s["counters"];
    EXPECT_DOUBLE_EQ(column_sum(rows, "contact_evaluations"),
                     c["contact_evaluations"].get<double>());
    EXPECT_DOUBLE_EQ(column_sum(rows, "point_updates"), c["contact_point_updates"].get<double>());
    EXPECT_DOUBLE_EQ(column_sum(rows, "lanes"), c["contact_lanes"].get<double>());
    EXPECT_DOUBLE_EQ(column_sum(rows, "model_evaluations"),
                     c["contact_constitutive_evaluations"].get<double>());
    EXPECT_DOUBLE_EQ(column_sum(rows, "model_substeps"), c["contact_model_substeps"].get<double>());
    EXPECT_GT(column_sum(rows, "interface_newton_iterations"), 0.0);
    EXPECT_DOUBLE_EQ(column_sum(rows, "factorisations"), c["linear_factorisations"].get<double>());
    EXPECT_DOUBLE_EQ(column_sum(rows, "krylov_steps"), c["linear_krylov_iterations"].get<double>());
    EXPECT_DOUBLE_EQ(column_sum(rows, "krylov_fallbacks"),
                     c["linear_krylov_fallbacks"].get<double>());
    EXPECT_GT(column_sum(rows, "krylov_steps"), 0.0); // the held factorisations were used
    // Seconds are written to 1e-4 s: each row rounds by at most 5e-5 s.
    EXPECT_LE(column_sum(rows, "contact_s"),
              s["timing"]["phases"]["contact_kernels"].get<double>() +
                  5.0e-5 * static_cast<double>(rows.size()));

    // Each increment: iterations 0, 1, 2, ... in order, at least newton_iterations + 1 checks
    // (a re-gather adds a check without a correction), the last one the residual accepted.
    std::size_t at = 0;
    for (std::size_t inc = 1; inc < h.rows.size(); ++inc) {
        int iteration = 0;
        std::size_t last = at;
        for (; at < rows.size() && rows[at].at("increment") == static_cast<double>(inc); ++at) {
            EXPECT_EQ(rows[at].at("iteration"), iteration++) << "increment " << inc;
            EXPECT_EQ(rows[at].at("stage"), h.number(inc, "stage"));
            EXPECT_GE(rows[at].at("seconds"), 0.0);
            last = at;
        }
        ASSERT_GT(iteration, 0) << "no rows for increment " << inc;
        EXPECT_GE(iteration, h.number(inc, "newton_iterations") + 1) << "increment " << inc;
        EXPECT_EQ(rows[last].at("residual"), h.number(inc, "residual")) << "increment " << inc;
    }
    EXPECT_EQ(at, rows.size()); // no rows of increments history.csv does not have

    // The costliest Algorithm 1 call, replayed alone, costs what the run counted for it.
    const nlohmann::json& costliest = s["costliest_call"];
    ASSERT_TRUE(costliest.is_object()) << s.dump(2);
    EXPECT_EQ(costliest["failure"], "none");
    const double substeps = costliest["model_substeps"].get<double>();
    EXPECT_GT(substeps, 0.0);
    EXPECT_LE(substeps, c["contact_model_substeps"].get<double>());
    const fs::path replay = test::fresh_dir("iteration-log-costliest");
    const auto again = test::run_cli_captured(
        {"run", costliest["replay"].get<std::string>(), "--out", replay.string()});
    ASSERT_EQ(again.code, 0) << again.err;
    EXPECT_EQ(test::summary(replay)["counters"]["model_substeps"].get<double>(), substeps);
}

TEST(IterationLog, WithoutTheOptionNoFileAndOtherKindsRefuseIt) {
    const fs::path dir = test::fresh_dir("iteration-log-off");
    ASSERT_EQ(test::run_cli_captured({"run", "scenes/fe-simple-shear-cnl-2d.toml", "--out",
                                      dir.string(), "--set", "stage.2.steps=1", "--set",
                                      "stage.2.displacement.1.change=0.00003"})
                  .code,
              0);
    EXPECT_FALSE(fs::exists(dir / IterationLog::file_name));
    EXPECT_FALSE(fs::exists(dir / costliest_call_file_name));

    const fs::path element = test::fresh_dir("iteration-log-element");
    const auto r = test::run_cli_captured({"run", "scenes/element-hypo-oedometer.toml", "--out",
                                           element.string(), "--iteration-log"});
    EXPECT_EQ(r.code, exit_code::bad_input);
    EXPECT_NE(r.err.find("--iteration-log"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("boundary-value"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(element / IterationLog::file_name));
}

} // namespace
} // namespace ifsim::io
