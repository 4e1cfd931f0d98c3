#include "io/output/admissibility_warnings.hpp"

#include <fmt/format.h>

namespace ifsim::io {

namespace {

nlohmann::ordered_json count_json(const AdmissibilityCount& c) {
    return {{"rows", c.rows},
            {"first_step", c.first_step},
            {"worst", c.worst},
            {"worst_step", c.worst_step}};
}

// One warning per kind of excess: "<rows> row(s) of the <who> (<model>) <what>, first at step
// <n>, <worst> at step <m><why>".
void warn(RunSummary& summary, const AdmissibilityCount& c, const std::string& code,
          const std::string& subject, const std::string& what, const std::string& worst,
          const std::string& why) {
    if (c.rows == 0) {
        return;
    }
    summary.warnings.push_back(
        {code, static_cast<double>(c.rows),
         fmt::format("{} row(s) of the {} {}, first at step {}, {} at step {}{}", c.rows, subject,
                     what, c.first_step, worst, c.worst_step, why)});
}

} // namespace

void add_admissibility(RunSummary& summary, const StateAdmissibility& a, const std::string& who,
                       const std::string& model) {
    summary.details["admissibility"][who] = {{"tension", count_json(a.tension)},
                                             {"void_ratio", count_json(a.void_ratio)}};
    const std::string subject = fmt::format("{} ({})", who, model);
    warn(summary, a.tension, who + "_tension", subject, "carry a tensile principal stress",
         fmt::format("largest +{:.3g} kPa", a.tension.worst),
         ": the model's own equations left the compressive region, where they do not describe "
         "sand");
    warn(summary, a.void_ratio, who + "_void_ratio", subject,
         "have a void ratio outside the model's bounds (hypoplasticity: [e_d, e_i] of the Bauer "
         "law at the row's pressure; any model: e > 0)",
         fmt::format("up to {:.3g} beyond", a.void_ratio.worst), "");
}

} // namespace ifsim::io
