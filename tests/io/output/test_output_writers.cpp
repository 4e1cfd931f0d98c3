// history.csv and summary.json writers: exact contract columns, numbers that read back to the
// same double, files that appear under their final names only when complete.

#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "io/element_test/element_history.hpp"
#include "io/output/history_writer.hpp"
#include "io/output/progress.hpp"
#include "io/output/summary_writer.hpp"
#include "kernels/parameter_sets.hpp"
#include "tests/io/scene_test_support.hpp"

namespace ifsim::io {
namespace {

namespace fs = std::filesystem;

std::string joined(const std::vector<std::string>& cols) {
    std::string s;
    for (const auto& c : cols) {
        s += (s.empty() ? "" : ",") + c;
    }
    return s;
}

const std::string contract_columns =
    "step,stage,eps11,eps22,eps33,eps12,eps13,eps23,s11,s22,s33,s12,s13,s23,e";

TEST(ElementHistoryColumns, FollowTheContractForEveryModel) {
    EXPECT_EQ(joined(element_history_columns(*parameter_sets::hypoplasticity("l4c"))),
              contract_columns + ",h11,h22,h33,h12,h13,h23");
    EXPECT_EQ(joined(element_history_columns(*parameter_sets::sanisand("karlsruhe-sand"))),
              contract_columns + ",a11,a22,a33,a12,a13,a23,z11,z22,z33,z12,z13,z23," +
                  "ain11,ain22,ain33,ain12,ain13,ain23");
    EXPECT_EQ(joined(element_history_columns(LinearElasticParams{})), contract_columns);
}

TEST(HistoryWriter, IsPartialUntilFinishedAndKeepsFullPrecision) {
    const fs::path dir = test::fresh_dir("history");
    HistoryWriter w(dir, {"step", "x", "y"});
    const double x = 0.1 + 0.2; // not representable in few digits
    const double y = -1.0 / 3.0e7;
    w.integer(3);
    w.real(x);
    w.real(y);
    w.end_row();
    EXPECT_TRUE(fs::exists(dir / "history.csv.partial"));
    EXPECT_FALSE(fs::exists(dir / "history.csv"));
    w.finish();
    EXPECT_FALSE(fs::exists(dir / "history.csv.partial"));
    ASSERT_TRUE(fs::exists(dir / "history.csv"));
    std::istringstream in(test::read_text(dir / "history.csv"));
    std::string header, row;
    std::getline(in, header);
    std::getline(in, row);
    EXPECT_EQ(header, "step,x,y");
    const auto c1 = row.find(',');
    const auto c2 = row.find(',', c1 + 1);
    EXPECT_EQ(row.substr(0, c1), "3");
    EXPECT_EQ(std::stod(row.substr(c1 + 1, c2 - c1 - 1)), x);
    EXPECT_EQ(std::stod(row.substr(c2 + 1)), y);
    EXPECT_EQ(w.rows(), 1u);
}

TEST(HistoryWriter, RejectsRowsOfTheWrongWidth) {
    HistoryWriter w(test::fresh_dir("history-width"), {"a", "b"});
    w.real(1.0);
    EXPECT_THROW(w.end_row(), std::logic_error);
}

TEST(HistoryWriter, UnwritableDirectoryIsAnErrorNamingTheFile) {
    try {
        HistoryWriter w("/nonexistent/dir", {"a"});
        FAIL();
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/history.csv.partial"),
                  std::string::npos);
    }
}

TEST(ElementHistoryRow, HasOneFieldPerColumn) {
    const fs::path dir = test::fresh_dir("element-row");
    const auto cols = element_history_columns(*parameter_sets::sanisand("karlsruhe-sand"));
    HistoryWriter w(dir, cols);
    ElementRow row;
    row.step = 4;
    row.stage = 2;
    row.strain = {-0.001, 0.0005, 0.0005, 0.0, 0.0, 0.0};
    row.state.assign(25, 0.25);
    write_element_row(w, row, 25);
    w.finish();
    std::istringstream in(test::read_text(dir / "history.csv"));
    std::string header, line;
    std::getline(in, header);
    std::getline(in, line);
    EXPECT_EQ(std::count(line.begin(), line.end(), ','), static_cast<long>(cols.size()) - 1);
    EXPECT_TRUE(line.starts_with("4,2,-0.001,0.0005,0.0005,0,0,0,0.25")) << line;
}

TEST(SummaryWriter, WritesAtomicallyWithTheContractFields) {
    const fs::path dir = test::fresh_dir("summary");
    RunSummary s;
    s.scene = "scenes/x.toml";
    s.kind = "element-test";
    s.ok = true;
    s.threads = 2;
    s.wall_s = 0.5;
    s.phases = {{"parse", 0.1}, {"constitutive", 0.3}};
    s.counters = {{"increments", 10},
                  {"newton_iterations", 0},
                  {"subincrements", 12},
                  {"constitutive_evaluations", 10}};
    s.details["model"] = "hypoplasticity";
    write_summary(dir, s);
    EXPECT_FALSE(fs::exists(dir / "summary.json.tmp"));
    const auto j = nlohmann::json::parse(test::read_text(dir / "summary.json"));
    EXPECT_EQ(j["scene"], "scenes/x.toml");
    EXPECT_EQ(j["kind"], "element-test");
    EXPECT_EQ(j["status"], "ok");
    EXPECT_FALSE(j.contains("reason"));
    EXPECT_EQ(j["threads"], 2);
    EXPECT_FALSE(j["revision"].get<std::string>().empty());
    EXPECT_DOUBLE_EQ(j["timing"]["wall_s"].get<double>(), 0.5);
    EXPECT_DOUBLE_EQ(j["timing"]["phases"]["constitutive"].get<double>(), 0.3);
    for (const char* c :
         {"increments", "newton_iterations", "subincrements", "constitutive_evaluations"}) {
        EXPECT_TRUE(j["counters"].contains(c)) << c;
    }
    EXPECT_EQ(j["model"], "hypoplasticity");
}

TEST(SummaryWriter, FailedRunsCarryTheReasonAndReplaceAnOldSummary) {
    const fs::path dir = test::fresh_dir("summary-failed");
    RunSummary ok;
    ok.ok = true;
    write_summary(dir, ok);
    RunSummary failed;
    failed.reason = "step 7: singular tangent";
    write_summary(dir, failed);
    const auto j = nlohmann::json::parse(test::read_text(dir / "summary.json"));
    EXPECT_EQ(j["status"], "failed");
    EXPECT_EQ(j["reason"], "step 7: singular tangent");
    EXPECT_TRUE(j["kind"].is_null());
}

TEST(ProgressLine, NeverModePrintsNothing) {
    std::FILE* f = std::tmpfile();
    {
        ProgressLine p(ProgressMode::never, 10, 1, f);
        p.update(5, 1);
        EXPECT_FALSE(p.enabled());
    }
    EXPECT_EQ(std::ftell(f), 0);
    std::fclose(f);
}

TEST(ProgressLine, AlwaysModeShowsOneLineAfterTheFirstSecond) {
    std::FILE* f = std::tmpfile();
    {
        ProgressLine p(ProgressMode::always, 10, 2, f);
        p.update(1, 1); // too early: nothing
        EXPECT_EQ(std::ftell(f), 0);
        std::this_thread::sleep_for(std::chrono::milliseconds(1050));
        p.update(5, 2);
        p.update(6, 2); // too soon after the last one: nothing more
        EXPECT_TRUE(p.shown());
    }
    std::rewind(f);
    char buf[256] = {};
    const std::size_t n = std::fread(buf, 1, sizeof(buf) - 1, f);
    std::fclose(f);
    const std::string text(buf, n);
    EXPECT_NE(text.find("step 5/10 (50%)  stage 2/2"), std::string::npos) << text;
    EXPECT_EQ(text.find("step 6/10"), std::string::npos) << text;
    EXPECT_EQ(text.back(), '\n');
}

} // namespace
} // namespace ifsim::io
