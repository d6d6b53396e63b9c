# Installs the exported targets as a CMake package: find_package(swba) -> swba::<module>.
include(CMakePackageConfigHelpers)
install(EXPORT swbaTargets NAMESPACE swba:: DESTINATION lib/cmake/swba)
configure_package_config_file(${CMAKE_CURRENT_SOURCE_DIR}/cmake/swbaConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/swbaConfig.cmake INSTALL_DESTINATION lib/cmake/swba)
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/swbaConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/swbaConfig.cmake ${CMAKE_CURRENT_BINARY_DIR}/swbaConfigVersion.cmake
  ${CMAKE_CURRENT_SOURCE_DIR}/cmake/FindSwbaCholmod.cmake DESTINATION lib/cmake/swba)
