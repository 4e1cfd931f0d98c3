#include "ratio_reporter.hpp"

#include <cstdio>
#include <regex>

namespace ifsim::bench {

void RatioReporter::ReportRuns(const std::vector<Run>& runs) {
    ConsoleReporter::ReportRuns(runs);
    for (const auto& r : runs) {
        if (r.run_type != Run::RT_Iteration || r.error_occurred) {
            continue;
        }
        const auto it = r.counters.find(counter_);
        if (it != r.counters.end()) {
            rate_[r.benchmark_name()] = it->second.value;
        }
    }
}

// Names look like "Family/points:N/simd:S/threads:T/real_time".
void RatioReporter::Finalize() {
    ConsoleReporter::Finalize();
    const std::regex pat(R"((.*)/points:(\d+)/simd:(\d)/threads:(\d)(.*))");
    std::printf("\n%-28s %9s %14s %14s %14s %14s\n", "family", "points", "simd/scalar@1",
                "simd/scalar@2", "2/1 threads simd", "2/1 threads scalar");
    for (const auto& [name, rate] : rate_) {
        std::smatch m;
        if (!std::regex_match(name, m, pat) || m[3] != "1" || m[4] != "1") {
            continue;
        }
        const std::string base = m[1].str() + "/points:" + m[2].str();
        const std::string tail = m[5].str();
        auto get = [&](int simd, int threads) {
            const auto it = rate_.find(base + "/simd:" + std::to_string(simd) +
                                       "/threads:" + std::to_string(threads) + tail);
            return it == rate_.end() ? 0.0 : it->second;
        };
        const double s1 = get(0, 1), v1 = get(1, 1), s2 = get(0, 2), v2 = get(1, 2);
        auto ratio = [](double a, double b) { return b > 0.0 && a > 0.0 ? a / b : 0.0; };
        std::printf("%-28s %9s %14.2f %14.2f %14.2f %14.2f\n", m[1].str().c_str(),
                    m[2].str().c_str(), ratio(v1, s1), ratio(v2, s2), ratio(v2, v1), ratio(s2, s1));
        (void)rate;
    }
    std::printf("(ratios of %s measured in this run; 0.00 = a configuration was not run)\n",
                counter_.c_str());
}

} // namespace ifsim::bench
