# Common compile flags and the swba_add_module() helper.
add_library(swba_build_flags INTERFACE)
target_compile_options(swba_build_flags INTERFACE -Wall -Wextra -Wpedantic -Wshadow=local)
if(SWBA_WERROR)
  target_compile_options(swba_build_flags INTERFACE -Werror)
endif()
if(SWBA_SANITIZE)
  target_compile_options(swba_build_flags INTERFACE -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  target_link_options(swba_build_flags INTERFACE -fsanitize=address,undefined)
endif()
install(TARGETS swba_build_flags EXPORT swbaTargets)

# swba_add_module(<name> DEPS <targets...>)
#   Builds modules/<name>/src/*.cpp into the library swba_<name> (alias swba::<name>),
#   public headers in modules/<name>/include/swba/<name>/.
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
    $<INSTALL_INTERFACE:include>)
  target_link_libraries(swba_${name} PUBLIC ${ARG_DEPS} PRIVATE swba_build_flags ${ARG_PRIVATE_DEPS})
  install(TARGETS swba_${name} EXPORT swbaTargets
    ARCHIVE DESTINATION lib LIBRARY DESTINATION lib RUNTIME DESTINATION bin)
  install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/ DESTINATION include)
endfunction()
