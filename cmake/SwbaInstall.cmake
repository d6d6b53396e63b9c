# Installs the exported targets as a CMake package: find_package(swba) -> swba::<module> for every
# module of SWBA_MODULES (swba::apps pulls in all of them).
include(CMakePackageConfigHelpers)
include(GNUInstallDirs)
set(SWBA_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/swba)
install(EXPORT swbaTargets NAMESPACE swba:: DESTINATION ${SWBA_INSTALL_CMAKEDIR})
string(REPLACE ";" ", " SWBA_MODULES_TEXT "${SWBA_MODULES}")
configure_package_config_file(${CMAKE_CURRENT_SOURCE_DIR}/cmake/swbaConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/swbaConfig.cmake INSTALL_DESTINATION ${SWBA_INSTALL_CMAKEDIR})
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/swbaConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
# The INI files, rawlog recipes and small reference data; the installed swba finds them relative to its
# own location (apps/swba/cli.cpp, share_dir) and names them in its --help.
install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/share/ DESTINATION ${CMAKE_INSTALL_DATADIR}/swba)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/swbaConfig.cmake ${CMAKE_CURRENT_BINARY_DIR}/swbaConfigVersion.cmake
  ${CMAKE_CURRENT_SOURCE_DIR}/cmake/FindSwbaCholmod.cmake DESTINATION ${SWBA_INSTALL_CMAKEDIR})

# Optional API documentation: `cmake --build <dir> --target doc` when Doxygen is installed
# (doc/Doxyfile.in; output in <build>/doc/html). Not part of the default build.
find_package(Doxygen QUIET)
if(DOXYGEN_FOUND)
  configure_file(${CMAKE_CURRENT_SOURCE_DIR}/doc/Doxyfile.in ${CMAKE_CURRENT_BINARY_DIR}/doc/Doxyfile @ONLY)
  add_custom_target(doc
    COMMAND ${DOXYGEN_EXECUTABLE} ${CMAKE_CURRENT_BINARY_DIR}/doc/Doxyfile
    WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR}/doc
    COMMENT "Doxygen: API reference of the public headers -> ${CMAKE_CURRENT_BINARY_DIR}/doc/html"
    VERBATIM)
endif()
