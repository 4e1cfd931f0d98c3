#pragma once
// Which BLAS UMFPACK's dense kernels run on. The choice belongs to Debian's libblas.so.3
// alternative (OpenBLAS after scripts/setup.sh); the build links that library first so that a
// BLAS named by another dependency cannot interpose its dgemm_ (CMakeLists.txt, ifsim_blas).

#include <string>

namespace ifsim::fem {

struct BlasBinding {
    std::string dgemm_library;    // the file whose dgemm_ the process calls
    std::string libblas_provider; // the file whose dgemm_ libblas.so.3 provides ("" if not loaded)
    bool openblas = false;        // OpenBLAS: its thread count is pinned (configure_blas)
    std::string openblas_core;    // OpenBLAS's kernel set now ("" for another BLAS)
    std::string
        openblas_detected_core; // the set OpenBLAS chose itself, if configure_blas replaced it
};

BlasBinding blas_binding();

// Sets up OpenBLAS (when it is the BLAS) before the first factorisation. Idempotent.
//
// Threads: OpenBLAS threads its kernels over all cores by default, and its threaded kernels sum
// in an order that depends on that count: the same run then differs in its last digits from one
// machine to another (measured on the fine §6 mesh). Pinned to one thread, a run's numbers
// depend on neither the machine nor --threads; UMFPACK's fronts on these meshes are too small
// for BLAS threads to pay (0.33 s per factorisation either way, docs/performance.md).
//
// Kernels: OpenBLAS picks its kernel set from the CPU's family and model when it loads. A CPU
// newer than the library (Debian 12's 0.3.21 on an Intel family 6 model 207, Emerald Rapids)
// falls back to the SSE3 "Prescott" set, whose dgemm ran 4x slower than the AVX-512 one there
// (docs/performance.md, "OpenBLAS's kernel set"). When OpenBLAS reports that fallback on a CPU
// with AVX2 or AVX-512, the set is chosen from the CPU's features instead (replacement_core),
// unless OPENBLAS_CORETYPE names one: the user's choice stands.
void configure_blas();
// OpenBLAS's current thread count; -1 for another BLAS.
int blas_threads();

// The kernel set to switch OpenBLAS to, or "" to keep `detected`: only OpenBLAS's fallback set
// is replaced, by the widest set the CPU's features carry.
struct CpuFeatures {
    bool avx512 = false; // AVX-512 F, BW, DQ and VL (the SkylakeX kernels use all four)
    bool avx2_fma = false;
    bool avx = false;
};
std::string replacement_core(const std::string& detected, const CpuFeatures& cpu);
CpuFeatures cpu_features();

} // namespace ifsim::fem
