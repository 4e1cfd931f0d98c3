#pragma once
// `ifsim run SCENE.toml --out DIR`: reads the scene (with --set overrides), runs it and writes
// DIR/history.csv and, last, DIR/summary.json. Returns the process exit code (exit_codes.hpp);
// messages go to stderr, one result line to stdout unless quiet.

#include <string>
#include <vector>

#include "io/output/progress.hpp"

namespace ifsim::io {

struct RunOptions {
    std::string scene;
    std::string out;
    std::vector<std::string> sets; // KEY=VALUE overrides, applied in order
    int threads = 0;               // 0 = all cores
    bool scalar = false;           // the scalar kernel path instead of SIMD
    ProgressMode progress = ProgressMode::automatic;
    bool quiet = false;
    bool replace = false;  // remove an earlier run's outputs in DIR instead of moving them aside
    bool fields = false;   // boundary-value: fields at the end of every stage
    long fields_every = 0; // boundary-value: fields every N increments
    long checkpoint_every = 0;     // boundary-value: a checkpoint every N increments
    double checkpoint_minutes = 0; // boundary-value: a checkpoint every M minutes
    bool resume = false;           // `ifsim resume DIR`: scene = DIR/scene.toml, out = DIR
    bool iteration_log = false;    // boundary-value: DIR/iterations.csv, a row per Newton iteration
};

int run_command(const RunOptions& options);

} // namespace ifsim::io
