#pragma once
// Units and meanings of the history.csv columns of every scene kind, for summary.json
// "columns" (docs/scenes.md has the long form). Compression negative; kPa and m.

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace ifsim::io {

struct ColumnDescription {
    std::string unit;    // "kPa", "m", "-" (dimensionless or a count)
    std::string meaning; // one line
};

// The description of a column of a run of `kind` ("element-test", "interface-test",
// "boundary-value"); nullopt for a column this table does not know.
std::optional<ColumnDescription> describe_column(std::string_view kind, std::string_view column);

// A column a run names itself (a recorder), with its description.
using NamedColumn = std::pair<std::string, ColumnDescription>;

// [{"name", "unit", "meaning"}] for every column (`named` first, then the kind's table);
// throws std::logic_error naming a column without a description (a new column must come with
// its unit).
nlohmann::ordered_json describe_columns(std::string_view kind,
                                        const std::vector<std::string>& columns,
                                        const std::vector<NamedColumn>& named = {});

} // namespace ifsim::io
