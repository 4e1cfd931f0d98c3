// libFuzzer harness: any bytes as a Gmsh mesh file (fuzz_inputs.hpp says what counts as a bug).

#include <cstddef>
#include <cstdint>

#include "fuzz/fuzz_inputs.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    ifsim::fuzz::read_gmsh_input({reinterpret_cast<const char*>(data), size});
    return 0;
}
