#pragma once
// The output folder of a run (`--out DIR`): the files a run writes there, and what happens to
// those of an earlier run before a new one starts. An earlier run's results are never
// destroyed silently and never left behind to pass for the new run's: by default they move
// into DIR/previous-<UTC time>/; with --replace they are removed. Other files in DIR (the
// user's own) are not touched.

#include <filesystem>
#include <string>
#include <vector>

namespace ifsim::io {

// Whether a name in DIR is one a run writes (summary.json, history.csv, their temporary
// names, the scene copy, field files and collections, plots made from the run, checkpoints).
bool is_run_output(const std::string& name);

struct FolderPreparation {
    std::vector<std::string> moved; // earlier outputs, by name
    std::filesystem::path moved_to; // DIR/previous-<time> (empty when nothing moved)
    bool removed = false;           // --replace: the earlier outputs were deleted
    // One line for the user ("" when DIR held no earlier run).
    std::string message(const std::filesystem::path& dir) const;
};

// Creates DIR if missing and clears it of an earlier run's outputs (moved aside, or removed
// when replace). Throws std::runtime_error naming the path when DIR cannot be prepared.
// Entries of DIR that are (or hold) one of `keep` (the scene file being run, its mesh) stay in
// place. With replace, fields/ loses only the field files a run writes; a fields/ folder that
// then still holds other files stays.
FolderPreparation prepare_run_folder(const std::filesystem::path& dir, bool replace,
                                     const std::vector<std::filesystem::path>& keep = {});

} // namespace ifsim::io
