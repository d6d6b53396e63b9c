# Find module for SuiteSparse CHOLMOD (Debian bookworm's libsuitesparse-dev 5.12 ships no CMake config).
# Defines the imported target SwbaCholmod::cholmod (own name: Ceres's FindSuiteSparse defines SuiteSparse::CHOLMOD).
find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
find_library(CHOLMOD_LIBRARY cholmod)
find_library(SUITESPARSE_CONFIG_LIBRARY suitesparseconfig)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(SwbaCholmod REQUIRED_VARS CHOLMOD_INCLUDE_DIR CHOLMOD_LIBRARY SUITESPARSE_CONFIG_LIBRARY)
if(SwbaCholmod_FOUND AND NOT TARGET SwbaCholmod::cholmod)
  add_library(SwbaCholmod::cholmod UNKNOWN IMPORTED)
  set_target_properties(SwbaCholmod::cholmod PROPERTIES
    IMPORTED_LOCATION "${CHOLMOD_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${CHOLMOD_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${SUITESPARSE_CONFIG_LIBRARY}")
endif()
mark_as_advanced(CHOLMOD_INCLUDE_DIR CHOLMOD_LIBRARY SUITESPARSE_CONFIG_LIBRARY)
