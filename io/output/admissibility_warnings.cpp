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

} // namespace

void add_admissibility(RunSummary& summary, const StateAdmissibility& a, const std::string& who,
                       const std::string& model) {
    summary.details["admissibility"][who] = {{"tension", count_json(a.tension)},
                                             {"void_ratio", count_json(a.void_ratio)}};
    if (a.tension.rows > 0) {
        summary.warnings.push_back(
            {who + "_tension", static_cast<double>(a.tension.rows),
             fmt::format("{} row(s) of the {} ({}) carry a tensile principal stress, first at "
                         "step {}, largest +{:.3g} kPa at step {}: the model's own equations "
                         "left the compressive region, where they do not describe sand",
                         a.tension.rows, who, model, a.tension.first_step, a.tension.worst,
                         a.tension.worst_step)});
    }
    if (a.void_ratio.rows > 0) {
        summary.warnings.push_back(
            {who + "_void_ratio", static_cast<double>(a.void_ratio.rows),
             fmt::format("{} row(s) of the {} ({}) have a void ratio outside the model's bounds "
                         "(hypoplasticity: [e_d, e_i] of the Bauer law at the row's pressure; any "
                         "model: e > 0), first at step {}, up to {:.3g} beyond at step {}",
                         a.void_ratio.rows, who, model, a.void_ratio.first_step, a.void_ratio.worst,
                         a.void_ratio.worst_step)});
    }
}

} // namespace ifsim::io
