#pragma once
// `ifsim sweep SWEEP.toml --out DIR [--jobs N]`: runs every member of a sweep (sweep_file.hpp)
// as `ifsim run` child processes, a queue over the cores, into DIR/runs/<id>/, and gathers
// them in DIR/sweep.csv (sweep_table.hpp) and DIR/sweep.json. Members whose folder holds an
// "ok" summary are not run again. Returns the process exit code (exit_codes.hpp): 0 when every
// run is ok, 3 when any failed, 2 for a bad sweep file, 1 when DIR cannot be written.

#include <string>

namespace ifsim::io {

struct SweepOptions {
    std::string sweep_file;
    std::string out;
    int jobs = 0;            // concurrent runs; 0 = one per core (at most one per run)
    int threads_per_run = 0; // 0 = the cores shared out between the concurrent runs
    bool scalar = false;     // every run on the scalar kernel path
    bool quiet = false;      // no line per finished run
    bool list = false;       // print the runs (id and overrides) and run nothing
    std::string executable;  // the ifsim that runs each member ("" = this executable)
};

int sweep_command(const SweepOptions& options);

} // namespace ifsim::io
