# Installs the framework and exports it as a CMake package, so a plugin built
# out of tree can do:
#   find_package(Trephine REQUIRED)
#   trephine_add_plugin(myplugin SOURCES MyDevice.cpp)
include(CMakePackageConfigHelpers)

set(_trephine_libraries trephine_math trephine_channels trephine_logs trephine_core trephine_geometry
    trephine_devices trephine_scene trephine_runtime trephine_data trephine_formats trephine_meshing_interface trephine_framework)
install(TARGETS ${_trephine_libraries} EXPORT TrephineTargets
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/trephine)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/framework DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/trephine
  FILES_MATCHING PATTERN "*.h")
install(EXPORT TrephineTargets NAMESPACE Trephine:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/Trephine)

configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/TrephineConfig.cmake.in
  ${PROJECT_BINARY_DIR}/TrephineConfig.cmake
  INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/Trephine
  PATH_VARS TREPHINE_PLUGIN_INSTALL_DIR)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/TrephineConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/TrephineConfig.cmake ${PROJECT_BINARY_DIR}/TrephineConfigVersion.cmake
  ${CMAKE_CURRENT_LIST_DIR}/TrephinePlugin.cmake
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/Trephine)
