# Debian 12's SuiteSparse 5.12 ships no CMake package for UMFPACK/KLU; this module finds them.
# Defines SuiteSparse::UMFPACK and SuiteSparse::KLU (each with its dependencies) on success.
find_path(SuiteSparse_INCLUDE_DIR umfpack.h PATH_SUFFIXES suitesparse)
find_library(SuiteSparse_CONFIG_LIBRARY suitesparseconfig)
find_library(SuiteSparse_AMD_LIBRARY amd)
find_library(SuiteSparse_COLAMD_LIBRARY colamd)
find_library(SuiteSparse_BTF_LIBRARY btf)
find_library(SuiteSparse_CHOLMOD_LIBRARY cholmod)
find_library(SuiteSparse_UMFPACK_LIBRARY umfpack)
find_library(SuiteSparse_KLU_LIBRARY klu)

set(SuiteSparse_UMFPACK_FOUND FALSE)
set(SuiteSparse_KLU_FOUND FALSE)
if(SuiteSparse_UMFPACK_LIBRARY AND SuiteSparse_CHOLMOD_LIBRARY AND SuiteSparse_AMD_LIBRARY)
  set(SuiteSparse_UMFPACK_FOUND TRUE)
endif()
if(SuiteSparse_KLU_LIBRARY AND SuiteSparse_BTF_LIBRARY AND SuiteSparse_COLAMD_LIBRARY)
  set(SuiteSparse_KLU_FOUND TRUE)
endif()

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(SuiteSparse
  REQUIRED_VARS SuiteSparse_INCLUDE_DIR SuiteSparse_CONFIG_LIBRARY
  HANDLE_COMPONENTS)

if(SuiteSparse_FOUND AND NOT TARGET SuiteSparse::config)
  add_library(SuiteSparse::config UNKNOWN IMPORTED)
  set_target_properties(SuiteSparse::config PROPERTIES IMPORTED_LOCATION ${SuiteSparse_CONFIG_LIBRARY}
                        INTERFACE_INCLUDE_DIRECTORIES ${SuiteSparse_INCLUDE_DIR})
  if(SuiteSparse_UMFPACK_FOUND)
    add_library(SuiteSparse::UMFPACK INTERFACE IMPORTED)
    target_link_libraries(SuiteSparse::UMFPACK INTERFACE ${SuiteSparse_UMFPACK_LIBRARY}
      ${SuiteSparse_CHOLMOD_LIBRARY} ${SuiteSparse_AMD_LIBRARY} ${SuiteSparse_COLAMD_LIBRARY}
      SuiteSparse::config)
  endif()
  if(SuiteSparse_KLU_FOUND)
    add_library(SuiteSparse::KLU INTERFACE IMPORTED)
    target_link_libraries(SuiteSparse::KLU INTERFACE ${SuiteSparse_KLU_LIBRARY} ${SuiteSparse_BTF_LIBRARY}
      ${SuiteSparse_AMD_LIBRARY} ${SuiteSparse_COLAMD_LIBRARY} SuiteSparse::config)
  endif()
endif()
mark_as_advanced(SuiteSparse_INCLUDE_DIR SuiteSparse_CONFIG_LIBRARY SuiteSparse_AMD_LIBRARY
  SuiteSparse_COLAMD_LIBRARY SuiteSparse_BTF_LIBRARY SuiteSparse_CHOLMOD_LIBRARY
  SuiteSparse_UMFPACK_LIBRARY SuiteSparse_KLU_LIBRARY)
