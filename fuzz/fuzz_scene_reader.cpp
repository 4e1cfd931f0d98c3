// libFuzzer harness: a scene's text with --set overrides (fuzz_inputs.hpp: the input format and
// what counts as a bug). Read as scenes/fuzz-input.toml of the source tree, so that the seeds'
// mesh files (meshes/...) are found.

#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz/fuzz_inputs.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const std::string scene_file = IFSIM_SOURCE_DIR "/scenes/fuzz-input.toml";
    ifsim::fuzz::read_scene_input({reinterpret_cast<const char*>(data), size}, scene_file);
    return 0;
}
