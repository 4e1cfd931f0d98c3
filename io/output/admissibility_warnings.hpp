#pragma once
// summary.json's account of states outside a model's sand region (engine/state_admissibility.hpp):
// a warning per kind of excess (the run is "degraded") and details["admissibility"][who] with
// the counts, first and worst steps, for scripts.

#include <string>

#include "engine/state_admissibility.hpp"
#include "io/output/summary_writer.hpp"

namespace ifsim::io {

// who: "material" (element test), "sample" or "interface" (interface test); the model's name
// goes into the message.
void add_admissibility(RunSummary& summary, const StateAdmissibility& a, const std::string& who,
                       const std::string& model);

} // namespace ifsim::io
