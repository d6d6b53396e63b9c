# Common compile flags and the swba_add_module() helper.
include(GNUInstallDirs)

# swba_build_flags: warning (and -Werror / sanitizer) flags for swba's own targets. It is a build-only
# dependency: libraries link it as $<BUILD_INTERFACE:swba_build_flags> and it is not installed, so the
# exported swba::<module> targets never carry these flags into a user's build.
add_library(swba_build_flags INTERFACE)
target_compile_options(swba_build_flags INTERFACE -Wall -Wextra -Wpedantic)
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")  # clang has no -Wshadow=local (the fuzz build uses clang)
  target_compile_options(swba_build_flags INTERFACE -Wshadow=local)
endif()
if(SWBA_WERROR)
  target_compile_options(swba_build_flags INTERFACE -Werror)
endif()
# clang's OpenMP-specific optimisation pass (OpenMPOpt) serves offloading; on our host-only parallel
# loops it took a third of the compile time of the OpenMP modules' sources under the sanitizers and moved
# no run time (doc/benchmarks/ci.md).
if(CMAKE_CXX_COMPILER_ID MATCHES "Clang")
  include(CheckCXXCompilerFlag)
  check_cxx_compiler_flag("-mllvm -openmp-opt-disable" SWBA_HAS_OPENMP_OPT_DISABLE)
  if(SWBA_HAS_OPENMP_OPT_DISABLE)
    target_compile_options(swba_build_flags INTERFACE "SHELL:-mllvm -openmp-opt-disable")
  endif()
endif()
if(SWBA_SANITIZE)
  target_compile_options(swba_build_flags INTERFACE -fsanitize=${SWBA_SANITIZERS} -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  target_link_options(swba_build_flags INTERFACE -fsanitize=${SWBA_SANITIZERS})
  # UBSan instruments swba's own code, not the system's headers (ubsan-ignorelist.txt says why).
  if(CMAKE_CXX_COMPILER_ID MATCHES "Clang" AND SWBA_SANITIZERS MATCHES "undefined")
    target_compile_options(swba_build_flags INTERFACE
      -fsanitize-ignorelist=${CMAKE_CURRENT_LIST_DIR}/ubsan-ignorelist.txt)
  endif()
endif()
# A fuzzing build (clang, SWBA_FUZZ and SWBA_SANITIZE, see fuzz/CMakeLists.txt) gives libFuzzer the
# coverage of swba's own code: the coverage instrumentation (fuzzer-no-link), whose callbacks the
# sanitizer runtime already linked into every executable provides, on every target (SWBA_FUZZ_COVERAGE
# "all", a campaign's build) or only on the listed modules (the readers' modules: the sanitizer suite's
# build, which also runs the fuzz smoke, keeps the estimator core free of its cost).
set(SWBA_FUZZ_COVERAGE "all" CACHE STRING
  "Targets with libFuzzer coverage in a fuzzing build: \"all\" or a list of modules (e.g. core;io;eval;apps)")
set(SWBA_FUZZ_INSTRUMENT OFF)
if(SWBA_FUZZ AND SWBA_SANITIZE AND CMAKE_CXX_COMPILER_ID MATCHES "Clang")
  set(SWBA_FUZZ_INSTRUMENT ON)
  if(SWBA_FUZZ_COVERAGE STREQUAL "all")
    target_compile_options(swba_build_flags INTERFACE -fsanitize=fuzzer-no-link)
  endif()
endif()

# SWBA_PCH: the system headers most sources parse, precompiled once per target (a module's sources
# share its flags), or once per group of targets whose flags are the same (the tests, the fuzz replays,
# the libFuzzer harnesses, the header checks) in a host target of its own that depends on nothing swba
# builds, so that no target of a group waits for another. Only system headers; like the unity build it
# can hide a source's or a header's missing system include, which the plain build (`./dev.sh run`, no
# unity, no SWBA_PCH) reports.
set(SWBA_PCH_HEADERS <algorithm> <array> <cmath> <cstdio> <fstream> <functional> <map> <memory> <set>
  <sstream> <stdexcept> <string> <vector> <Eigen/Core> <Eigen/Cholesky> <Eigen/Geometry>
  <mrpt/poses/CPose3D.h>)
# swba_target_pch(<target> [REUSE_FROM <host>]): the target's own precompiled headers, or its group's
# (a host of swba_add_pch_host).
function(swba_target_pch target)
  cmake_parse_arguments(ARG "" "REUSE_FROM" "" ${ARGN})
  if(NOT SWBA_PCH)
    return()
  elseif(ARG_REUSE_FROM)
    target_precompile_headers(${target} REUSE_FROM ${ARG_REUSE_FROM})
  else()
    target_precompile_headers(${target} PRIVATE ${SWBA_PCH_HEADERS})
  endif()
endfunction()
# swba_add_pch_host(<host> [EXTRA <headers...>] [LIBS <targets...>] [DEFINITIONS <defs...>]
#   [OPTIONS <options...>]): the host of a group, compiled with swba_build_flags and what LIBS,
#   DEFINITIONS and OPTIONS add — the same flags as its group's targets (clang refuses a header
#   precompiled with others). LIBS: imported targets only (their usage requirements, no build).
function(swba_add_pch_host host)
  cmake_parse_arguments(ARG "" "" "EXTRA;LIBS;DEFINITIONS;OPTIONS" ${ARGN})
  if(NOT SWBA_PCH)
    return()
  endif()
  set(src ${CMAKE_CURRENT_BINARY_DIR}/CMakeFiles/${host}.cpp)
  file(CONFIGURE OUTPUT ${src} CONTENT "// ${host}: precompiled headers of a group of targets (SWBA_PCH)\n")
  add_library(${host} OBJECT ${src})
  target_link_libraries(${host} PRIVATE Eigen3::Eigen mrpt::poses swba_build_flags ${ARG_LIBS})
  target_compile_definitions(${host} PRIVATE ${ARG_DEFINITIONS})
  target_compile_options(${host} PRIVATE ${ARG_OPTIONS})
  target_precompile_headers(${host} PRIVATE ${SWBA_PCH_HEADERS} ${ARG_EXTRA})
endfunction()

# swba_add_module(<name> DEPS <targets...> PRIVATE_DEPS <targets...>)
#   Builds modules/<name>/src/*.cpp into the static library swba_<name> (alias swba::<name>, exported
#   as swba::<name>), public headers in modules/<name>/include/swba/<name>/.
#   DEPS: used by the public headers (propagated to users). PRIVATE_DEPS: used only by the sources;
#   for a static library they still appear in the export as $<LINK_ONLY:...>, so each must be an
#   imported target that swbaConfig.cmake finds (find_dependency) before including the targets.
function(swba_add_module name)
  cmake_parse_arguments(ARG "" "" "DEPS;PRIVATE_DEPS" ${ARGN})
  file(GLOB_RECURSE srcs CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/*.cpp)
  if(NOT srcs)  # a module being started: keep the target valid
    set(srcs ${CMAKE_CURRENT_BINARY_DIR}/swba_${name}_empty.cpp)
    file(WRITE ${srcs} "// module ${name} has no sources yet\n")
  endif()
  add_library(swba_${name} STATIC ${srcs})
  add_library(swba::${name} ALIAS swba_${name})
  set_target_properties(swba_${name} PROPERTIES EXPORT_NAME ${name} POSITION_INDEPENDENT_CODE ON)
  target_include_directories(swba_${name} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_compile_features(swba_${name} PUBLIC cxx_std_17)
  target_link_libraries(swba_${name} PUBLIC ${ARG_DEPS}
    PRIVATE $<BUILD_INTERFACE:swba_build_flags> ${ARG_PRIVATE_DEPS})
  if(SWBA_FUZZ_INSTRUMENT AND NOT SWBA_FUZZ_COVERAGE STREQUAL "all" AND name IN_LIST SWBA_FUZZ_COVERAGE)
    target_compile_options(swba_${name} PRIVATE -fsanitize=fuzzer-no-link)
  endif()
  if(SWBA_SANITIZE)  # objects built with sanitizers need the runtime at the user's link step
    target_link_options(swba_${name} INTERFACE $<INSTALL_INTERFACE:-fsanitize=${SWBA_SANITIZERS}>)
  endif()
  swba_target_pch(swba_${name})
  set_property(GLOBAL APPEND PROPERTY SWBA_MODULE_INCLUDE_DIRS "${name}=${CMAKE_CURRENT_SOURCE_DIR}/include")
  install(TARGETS swba_${name} EXPORT swbaTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
    FILES_MATCHING PATTERN "*.h")
endfunction()
