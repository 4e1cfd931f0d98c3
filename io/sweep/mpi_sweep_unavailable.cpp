// Built without MPI (IFSIM_MPI=OFF or no MPI found): a sweep started under mpirun stops with a
// message instead of running the whole sweep once per rank into the same folder.

#include <fmt/format.h>

#include "io/cli/exit_codes.hpp"
#include "io/sweep/mpi_sweep.hpp"

namespace ifsim::io {

int run_on_mpi_ranks(const SweepOptions&,
                     const std::function<int(const SweepLayout&, RemoteWorkers&)>&) {
    fmt::print(stderr, "ifsim: error: started by an MPI launcher, but this ifsim was built "
                       "without MPI (install libopenmpi-dev and configure again, or run "
                       "without mpirun)\n");
    return exit_code::bad_input;
}

} // namespace ifsim::io
