# install.build_example: configures and builds examples/ against the installed package only.
# -DPREFIX -DSOURCE -DBINARY -DGENERATOR -DCXX -DBUILD_TYPE
file(REMOVE_RECURSE ${BINARY})
if(NOT BUILD_TYPE)
  set(BUILD_TYPE Release)
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE} -B ${BINARY} -G ${GENERATOR}
    -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_BUILD_TYPE=${BUILD_TYPE} -DCMAKE_PREFIX_PATH=${PREFIX}
    -DCMAKE_FIND_PACKAGE_NO_PACKAGE_REGISTRY=ON
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "configuring examples/ against ${PREFIX} failed (${rc}):\n${out}\n${err}")
endif()
# The package must have come from the temporary prefix, not from the build tree or elsewhere.
file(STRINGS ${BINARY}/CMakeCache.txt swba_dir REGEX "^swba_DIR:")
string(FIND "${swba_dir}" "${PREFIX}/" pos)
if(NOT pos GREATER -1)
  message(FATAL_ERROR "find_package(swba) did not use the installed package in ${PREFIX}: ${swba_dir}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${BINARY} -j2
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "building examples/ failed (${rc}):\n${out}\n${err}")
endif()
# Warnings of the user's own compile must not be swba's: no -Werror/-W flags on the example's compile line.
file(GLOB_RECURSE flag_files ${BINARY}/CMakeFiles/swba_online_slam.dir/flags.make)
if(flag_files)
  file(READ ${flag_files} flags)
  foreach(word -Werror -Wall -Wshadow)
    string(FIND "${flags}" "${word}" pos)
    if(NOT pos EQUAL -1)
      message(FATAL_ERROR "the example's compile flags contain ${word} from the package:\n${flags}")
    endif()
  endforeach()
endif()
# The embedding API is enough for an online application: no example links the applications' library.
file(GLOB_RECURSE link_files ${BINARY}/CMakeFiles/*/link.txt)
foreach(f ${link_files})
  file(READ ${f} link_line)
  if(link_line MATCHES "libswba_apps")
    message(FATAL_ERROR "${f} links swba::apps (the embedding API must do without it):\n${link_line}")
  endif()
endforeach()
message(STATUS "built ${BINARY}/swba_online_slam with ${swba_dir}")
