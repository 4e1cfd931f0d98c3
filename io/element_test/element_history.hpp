#pragma once
// The columns of an element test's history.csv (scene-format.md): step, stage, the six strain
// and six stress components, e, then the model's state: h11..h23 for hypoplasticity;
// a11..a23 (back-stress ratio alpha), z11..z23 (fabric) and ain11..ain23 (alpha at the last
// load reversal) for sanisand; nothing more for linear-elastic.

#include <string>
#include <vector>

#include "engine/element_test_driver.hpp"
#include "io/output/history_writer.hpp"

namespace ifsim::io {

std::vector<std::string> element_history_columns(const MaterialChoice& material);

// One row: the engine's row in the column order above, with the first reported_state entries
// of the state (reported_state_size(), engine/model_registry.hpp).
void write_element_row(HistoryWriter& out, const ElementRow& row, int reported_state);

} // namespace ifsim::io
