# trephine_add_plugin(<name> SOURCES <files...> [LINK <targets...>]
#                     [OUTPUT_DIRECTORY <dir>] [NO_INSTALL])
#
# Builds a Trephine plugin: a shared library named trephine_<name>.so that
# exports one registration function, `trephine_register_plugin`. A scene
# loads it with <RequiredPlugin name="<name>"/>. Used by the plugins of this
# project and, through the exported package, by plugins built out of tree.
function(trephine_add_plugin name)
  cmake_parse_arguments(ARG "NO_INSTALL" "OUTPUT_DIRECTORY" "SOURCES;LINK" ${ARGN})
  set(target trephine_plugin_${name})
  add_library(${target} MODULE ${ARG_SOURCES})
  set_property(GLOBAL APPEND PROPERTY TREPHINE_PLUGIN_TARGETS ${target})
  target_link_libraries(${target} PRIVATE Trephine::framework ${ARG_LINK})
  set_target_properties(${target} PROPERTIES
    PREFIX ""
    OUTPUT_NAME "trephine_${name}"
    CXX_VISIBILITY_PRESET hidden
    VISIBILITY_INLINES_HIDDEN ON)
  if(ARG_OUTPUT_DIRECTORY)
    set_target_properties(${target} PROPERTIES LIBRARY_OUTPUT_DIRECTORY ${ARG_OUTPUT_DIRECTORY})
  elseif(DEFINED TREPHINE_PLUGIN_OUTPUT_DIR)
    set_target_properties(${target} PROPERTIES LIBRARY_OUTPUT_DIRECTORY ${TREPHINE_PLUGIN_OUTPUT_DIR})
  endif()
  if(PROJECT_NAME STREQUAL "Trephine")
    # Installed in <libdir>/trephine/plugins, the plugin finds the framework
    # libraries two levels up; the project-wide $ORIGIN/../<libdir> would miss
    # those the program does not load itself (libtrephine_devices.so).
    file(RELATIVE_PATH to_libdir /${TREPHINE_PLUGIN_INSTALL_DIR} /${CMAKE_INSTALL_LIBDIR})
    set_target_properties(${target} PROPERTIES INSTALL_RPATH "$ORIGIN/${to_libdir}")
  else()
    # Out of tree: keep the installed Trephine's library directory in the RPATH.
    set_target_properties(${target} PROPERTIES INSTALL_RPATH_USE_LINK_PATH ON)
  endif()
  if(NOT ARG_NO_INSTALL AND DEFINED TREPHINE_PLUGIN_INSTALL_DIR AND PROJECT_NAME STREQUAL "Trephine")
    install(TARGETS ${target} LIBRARY DESTINATION ${TREPHINE_PLUGIN_INSTALL_DIR})
  endif()
endfunction()
