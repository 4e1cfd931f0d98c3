#include <cstdlib>

#include "io/sweep/mpi_sweep.hpp"

namespace ifsim::io {

bool launched_by_mpi() {
    // Open MPI's mpirun, and the PMI / PMIx environments of MPICH, Slurm's srun and others.
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"}) {
        if (std::getenv(name) != nullptr) {
            return true;
        }
    }
    return false;
}

} // namespace ifsim::io
