// Built without Ceres Solver (IFSIM_CERES=OFF or libceres-dev missing): `ifsim calibrate`
// says so instead of fitting.

#include <fmt/format.h>

#include "io/calibrate/calibrate_command.hpp"
#include "io/cli/exit_codes.hpp"

namespace ifsim::io {

int calibrate_command(const CalibrateOptions&) {
    fmt::print(stderr, "ifsim calibrate: error: this ifsim was built without Ceres Solver "
                       "(install libceres-dev and configure again)\n");
    return exit_code::bad_input;
}

} // namespace ifsim::io
