#pragma once
// Which BLAS UMFPACK's dense kernels run on. The choice belongs to Debian's libblas.so.3
// alternative (OpenBLAS after scripts/setup.sh); the build links that library first so that a
// BLAS named by another dependency cannot interpose its dgemm_ (CMakeLists.txt, ifsim_blas).

#include <string>

namespace ifsim::fem {

struct BlasBinding {
    std::string dgemm_library;    // the file whose dgemm_ the process calls
    std::string libblas_provider; // the file whose dgemm_ libblas.so.3 provides ("" if not loaded)
    bool openblas = false;        // OpenBLAS: its thread count is pinned (pin_blas_threads)
};

BlasBinding blas_binding();

// OpenBLAS threads its kernels over all cores by default, and its threaded kernels sum in an
// order that depends on that count: the same run then differs in its last digits from one
// machine to another (measured on the fine §6 mesh). Pinned to one thread, a run's numbers
// depend on neither the machine nor --threads; UMFPACK's fronts on these meshes are too small
// for BLAS threads to pay (0.33 s per factorisation either way, docs/performance.md). Idempotent.
void pin_blas_threads();
// OpenBLAS's current thread count; -1 for another BLAS.
int blas_threads();

} // namespace ifsim::fem
