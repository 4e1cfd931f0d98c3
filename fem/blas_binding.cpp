#include "fem/blas_binding.hpp"

#include <cstdlib>
#include <mutex>
#include <strings.h>

#include <dlfcn.h>

namespace ifsim::fem {
namespace {

std::string file_of(void* symbol) {
    Dl_info info{};
    if (symbol == nullptr || dladdr(symbol, &info) == 0 || info.dli_fname == nullptr) {
        return {};
    }
    return info.dli_fname;
}

template <class F>
F openblas_function(const char* name) {
    return reinterpret_cast<F>(dlsym(RTLD_DEFAULT, name));
}

std::string openblas_core() {
    using GetCore = char* (*)();
    if (auto get = openblas_function<GetCore>("openblas_get_corename")) {
        if (const char* name = get()) {
            return name;
        }
    }
    return {};
}

// What configure_blas replaced, for summary.json.
std::string& detected_core_record() {
    static std::string detected;
    return detected;
}

// OpenBLAS's dynamic-architecture builds choose their kernel set in gotoblas_dynamic_init,
// which reads OPENBLAS_CORETYPE first; gotoblas_dynamic_quit clears the choice. Both are
// exported by every such build. Called before the first BLAS call, so no buffer or thread of
// OpenBLAS holds anything tied to the old set.
void switch_openblas_core(const std::string& core) {
    using Hook = void (*)();
    auto quit = openblas_function<Hook>("gotoblas_dynamic_quit");
    auto init = openblas_function<Hook>("gotoblas_dynamic_init");
    if (quit == nullptr || init == nullptr) {
        return; // not a dynamic-architecture build: its kernels are fixed at build time
    }
    const std::string detected = openblas_core();
    setenv("OPENBLAS_CORETYPE", core.c_str(), 1);
    quit();
    init();
    unsetenv("OPENBLAS_CORETYPE"); // child processes detect for themselves
    if (strcasecmp(openblas_core().c_str(), core.c_str()) == 0) {
        detected_core_record() = detected;
    }
}

} // namespace

CpuFeatures cpu_features() {
    CpuFeatures f;
#if defined(__x86_64__) || defined(__i386__)
    __builtin_cpu_init();
    f.avx512 = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
               __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl");
    f.avx2_fma = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    f.avx = __builtin_cpu_supports("avx");
#endif
    return f;
}

std::string replacement_core(const std::string& detected, const CpuFeatures& cpu) {
    // OpenBLAS names its fallback "Prescott" (SSE3); on a CPU that old nothing wider exists.
    if (strcasecmp(detected.c_str(), "Prescott") != 0) {
        return {};
    }
    if (cpu.avx512) {
        return "SkylakeX";
    }
    if (cpu.avx2_fma) {
        return "Haswell";
    }
    if (cpu.avx) {
        return "Sandybridge";
    }
    return {};
}

BlasBinding blas_binding() {
    BlasBinding b;
    b.dgemm_library = file_of(dlsym(RTLD_DEFAULT, "dgemm_"));
    // RTLD_NOLOAD: only a libblas.so.3 the process already has (through UMFPACK or the build)
    if (void* handle = dlopen("libblas.so.3", RTLD_LAZY | RTLD_NOLOAD)) {
        b.libblas_provider = file_of(dlsym(handle, "dgemm_"));
        dlclose(handle);
    }
    b.openblas = dlsym(RTLD_DEFAULT, "openblas_set_num_threads") != nullptr;
    b.openblas_core = openblas_core();
    b.openblas_detected_core = detected_core_record();
    return b;
}

void configure_blas() {
    static std::once_flag once;
    std::call_once(once, [] {
        using SetThreads = void (*)(int);
        auto set = openblas_function<SetThreads>("openblas_set_num_threads");
        if (set == nullptr) {
            return; // another BLAS
        }
        if (std::getenv("OPENBLAS_CORETYPE") == nullptr) {
            const std::string core = replacement_core(openblas_core(), cpu_features());
            if (!core.empty()) {
                switch_openblas_core(core);
            }
        }
        set(1);
    });
}

int blas_threads() {
    using GetThreads = int (*)();
    if (auto get = openblas_function<GetThreads>("openblas_get_num_threads")) {
        return get();
    }
    return -1;
}

} // namespace ifsim::fem
