#pragma once
// Every option of one Algorithm 1 call (ContactOptions with its InterfaceSettings and the
// interface model's own IntegrationSettings) as the [algorithm1] table of an interface-point
// scene, keyed by the C++ field names (the model's integration with prefix model_). A replay
// writes all of them, so the replayed call runs with the failed call's options exactly; a
// hand-written scene may leave any out (then the interface test's defaults apply). The
// formulation and the dimension are keys of [interface] and [point].

#include <toml++/toml.h>

#include "engine/contact_update.hpp"
#include "io/scene/table_reader.hpp"

namespace ifsim::io {

// The options as a TOML table (every key).
toml::table algorithm1_table(const ContactOptions& options);

// Reads the keys present in t into `options` (bounds checked). Throws SceneError.
void read_algorithm1(const TableReader& t, ContactOptions& options);

} // namespace ifsim::io
