#pragma once
// Words for TOML values in error messages ("got a string \"abc\"") and where they stand.

#include <string>
#include <vector>

#include <toml++/toml.h>

namespace ifsim::io {

// "a string \"x\"", "an integer 3", "a number 0.5", "an array of 4 values", "a table", ...
std::string describe_node(const toml::node& node);

// Line of the node in the scene file; 0 when it has none there (e.g. given with --set).
int line_in_file(const toml::node& node);

// True when the node's value came from a command-line override.
bool from_override(const toml::node& node);

// The keys of a table in the order they stand in the file (toml++ keeps them sorted); keys
// without a line (from --set) last, in sorted order.
std::vector<std::string> keys_in_file_order(const toml::table& table);

} // namespace ifsim::io
