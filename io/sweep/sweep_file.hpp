#pragma once
// A sweep file (`ifsim sweep SWEEP.toml`): a base scene (or several) and the values of scene
// keys to run it with. Keys are the `--set` keys of `ifsim run`; their values are lists,
// combined as a full grid ([grid]: every combination, the last key varying fastest) and/or
// zipped ([zip]: the n-th values of every key together). [set] holds overrides given to every
// run. Example:
//
//   scene = "simple-shear-cnl-stutz.toml"     # or a list; relative to the sweep file
//   [grid]
//   "interface.roughness" = [0.8, 0.9, 1.0]
//   "interface.shear_band_thickness" = [0.002, 0.003]
//   [set]
//   "interface.subincrement" = "adaptive"

#include <filesystem>
#include <string>
#include <vector>

#include <toml++/toml.h>

namespace ifsim::io {

// One swept key with its values as TOML text (what `--set KEY=VALUE` gets) and as the text a
// table shows (strings without quotes).
struct SweepAxis {
    std::string key;
    std::vector<std::string> values;  // TOML text: 0.8, 1.0, "adaptive", [1, 2]
    std::vector<std::string> display; // 0.8, 1.0, adaptive, [1, 2]
};

struct SweepFile {
    std::filesystem::path file;
    std::vector<std::string> scenes;          // as written in the file
    std::vector<std::filesystem::path> paths; // resolved against the file's folder
    std::vector<SweepAxis> grid;              // in the order of the file
    std::vector<SweepAxis> zip;               // all of one length
    std::vector<std::string> fixed;           // KEY=VALUE given to every run
    std::size_t runs() const;                 // scenes x grid combinations x zip length
};

// Reads and checks a sweep file. Throws SceneError naming the file, the key and what was
// expected (a missing scene file, an empty list, zip lists of different lengths, ...).
SweepFile read_sweep_file(const std::filesystem::path& file);

// A scene value as TOML text for `--set` (doubles in their shortest exact form, always with a
// decimal point or exponent so they stay floats).
std::string toml_value_text(const toml::node& node);

} // namespace ifsim::io
