# Warnings, instruction set and sanitizers for every ifsim target (through ifsim_options).
add_library(ifsim_options INTERFACE)
target_compile_options(ifsim_options INTERFACE -Wall -Wextra -Wpedantic)
# Position-independent code (for the Python module) keeps calls between our own functions
# inlinable: no symbol interposition is relied on.
target_compile_options(ifsim_options INTERFACE $<$<CXX_COMPILER_ID:GNU>:-fno-semantic-interposition>)
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
  # GCC 12's own AVX-512 intrinsic headers trip -Wuninitialized through _mm512_undefined_*()
  # when inlined into xsimd's pow/log (GCC bug 105593, fixed in GCC 13). Not our code.
  target_compile_options(ifsim_options INTERFACE -Wno-uninitialized)
endif()

if(IFSIM_PORTABLE)
  # x86-64-v2 (SSE4.2): runs on any x86-64 machine of the last decade; xsimd picks SSE lanes.
  set(IFSIM_ARCH_FLAGS -march=x86-64-v2)
else()
  set(IFSIM_ARCH_FLAGS -march=native)
endif()
target_compile_options(ifsim_options INTERFACE ${IFSIM_ARCH_FLAGS})

if(IFSIM_SANITIZE)
  target_compile_options(ifsim_options INTERFACE -fsanitize=address,undefined -fno-omit-frame-pointer
                                                 -fno-sanitize-recover=undefined)
  target_link_options(ifsim_options INTERFACE -fsanitize=address,undefined)
endif()
if(IFSIM_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "ifsim: IFSIM_FUZZ needs clang (libFuzzer); use the sanitize preset")
  endif()
  # Coverage feedback from all of ifsim's code; fuzz/ links the libFuzzer driver.
  target_compile_options(ifsim_options INTERFACE -fsanitize=fuzzer-no-link)
endif()

# Check at configure time which SIMD width the kernels get, so the build reports it and the
# library and user code cannot silently mix instruction sets (all targets share these flags).
include(CheckCXXSourceRuns)
set(CMAKE_REQUIRED_FLAGS "${IFSIM_ARCH_FLAGS}")
set(CMAKE_REQUIRED_INCLUDES ${xsimd_INCLUDE_DIRS})
get_target_property(_xsimd_inc xsimd INTERFACE_INCLUDE_DIRECTORIES)
set(CMAKE_REQUIRED_INCLUDES ${_xsimd_inc})
string(REPLACE ";" " " CMAKE_REQUIRED_FLAGS "${IFSIM_ARCH_FLAGS} -std=c++20")
file(WRITE ${CMAKE_BINARY_DIR}/ifsim_lanes.cpp
  "#include <xsimd/xsimd.hpp>\n#include <cstdio>\nint main(){std::printf(\"%zu %s\\n\", xsimd::batch<double>::size, xsimd::default_arch::name());}\n")
try_run(_run_res _compile_res ${CMAKE_BINARY_DIR}/ifsim_lanes_probe ${CMAKE_BINARY_DIR}/ifsim_lanes.cpp
  CMAKE_FLAGS "-DINCLUDE_DIRECTORIES=${_xsimd_inc}"
  COMPILE_DEFINITIONS ${IFSIM_ARCH_FLAGS} -std=c++20
  RUN_OUTPUT_VARIABLE IFSIM_LANES_OUT)
if(NOT _compile_res OR NOT _run_res EQUAL 0)
  message(FATAL_ERROR "ifsim: cannot build or run an xsimd probe with ${IFSIM_ARCH_FLAGS}")
endif()
string(STRIP "${IFSIM_LANES_OUT}" IFSIM_LANES_OUT)
message(STATUS "ifsim: SIMD lanes and architecture: ${IFSIM_LANES_OUT} (flags ${IFSIM_ARCH_FLAGS})")
