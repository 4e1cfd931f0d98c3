#include "fem/blas_binding.hpp"

#include <mutex>

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

} // namespace

BlasBinding blas_binding() {
    BlasBinding b;
    b.dgemm_library = file_of(dlsym(RTLD_DEFAULT, "dgemm_"));
    // RTLD_NOLOAD: only a libblas.so.3 the process already has (through UMFPACK or the build)
    if (void* handle = dlopen("libblas.so.3", RTLD_LAZY | RTLD_NOLOAD)) {
        b.libblas_provider = file_of(dlsym(handle, "dgemm_"));
        dlclose(handle);
    }
    b.openblas = dlsym(RTLD_DEFAULT, "openblas_set_num_threads") != nullptr;
    return b;
}

void pin_blas_threads() {
    static std::once_flag once;
    std::call_once(once, [] {
        using SetThreads = void (*)(int);
        if (auto set =
                reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"))) {
            set(1);
        }
    });
}

int blas_threads() {
    using GetThreads = int (*)();
    if (auto get = reinterpret_cast<GetThreads>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"))) {
        return get();
    }
    return -1;
}

} // namespace ifsim::fem
