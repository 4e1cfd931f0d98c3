// `ifsim kernel-bench` options of the continuum integration: the scheme sets the rate
// evaluations per substep, h integrated with the stress (--no-split) needs more of them than
// h on its own, and --cold starts every repetition without the carried substep size.

#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "io/cli/kernel_bench.hpp"

namespace ifsim::io {
namespace {

nlohmann::ordered_json hypo_bench(const std::string& scheme, bool no_split, bool cold) {
    KernelBenchOptions o;
    o.model = "hypoplasticity";
    o.points = 64;
    o.threads = 1;
    o.seconds = 0.02;
    o.strain_increment = 1.0e-5;
    o.scheme = scheme;
    o.no_split = no_split;
    o.cold = cold;
    return run_kernel_bench(o);
}

double per_substep(const nlohmann::ordered_json& j) {
    return (j["rate_evaluations_per_evaluation"].get<double>()) /
           (j["substeps_per_evaluation"].get<double>() +
            j["rejected_substeps_per_evaluation"].get<double>());
}

TEST(KernelBenchIntegration, SchemeSplitAndColdChangeTheWork) {
    const auto rkf23 = hypo_bench("rkf23", false, false);
    const auto heun = hypo_bench("heun", false, false);
    const auto coupled = hypo_bench("rkf23", true, true);
    EXPECT_EQ(rkf23["scheme"], "rkf23");
    EXPECT_EQ(rkf23["split_internal"], true);
    EXPECT_EQ(coupled["carried_substep"], false);
    EXPECT_DOUBLE_EQ(per_substep(rkf23), 3.0);
    EXPECT_DOUBLE_EQ(per_substep(heun), 2.0);
    // h with the stress: its error sets the substeps (measured 11.5 evaluations against 3.0)
    EXPECT_GT(coupled["rate_evaluations_per_evaluation"].get<double>(),
              2.0 * rkf23["rate_evaluations_per_evaluation"].get<double>());
    EXPECT_EQ(rkf23["failed_points"], 0);
    EXPECT_EQ(coupled["failed_points"], 0);
}

TEST(KernelBenchIntegration, BadSchemeIsAnError) {
    KernelBenchOptions o;
    o.model = "hypoplasticity";
    o.points = 8;
    o.seconds = 0.02;
    o.scheme = "rk45";
    EXPECT_THROW(run_kernel_bench(o), std::invalid_argument);
}

} // namespace
} // namespace ifsim::io
