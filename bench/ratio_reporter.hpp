#pragma once
// A console reporter that also prints, at the end of a run, the ratios the project's claims
// rest on: SIMD over scalar (same threads) and 2 threads over 1 (same path), per benchmark
// family and batch size, all measured in the same process run.

#include <map>
#include <string>

#include <benchmark/benchmark.h>

namespace ifsim::bench {

class RatioReporter : public benchmark::ConsoleReporter {
public:
    explicit RatioReporter(std::string counter) : counter_(std::move(counter)) {}
    void ReportRuns(const std::vector<Run>& runs) override;
    void Finalize() override;

private:
    std::string counter_;
    std::map<std::string, double> rate_; // benchmark name -> counter value
};

} // namespace ifsim::bench
