# trephine_check_plugin_isolation(<plugin folders...>)
#
# Plugins meet only through the framework: no library of one plugin's folder
# may link, directly or through another library, a library of another
# plugin's folder. Checked when the build is configured, so a link line
# that names another plugin's library fails the build at once, naming both.
# Only this project's own targets (trephine_*, not imported) are owned by a
# folder; third-party targets found in a plugin's folder (Bullet's) are not.

# The plugin folder (its name under plugins/) of `target`, or "" for one of
# the framework's, a third party's or a test's.
function(_trephine_plugin_of target out)
  set(${out} "" PARENT_SCOPE)
  if(NOT TARGET ${target})
    return()
  endif()
  get_target_property(aliased ${target} ALIASED_TARGET)
  if(aliased)
    set(target ${aliased})
  endif()
  get_target_property(imported ${target} IMPORTED)
  if(imported OR NOT target MATCHES "^trephine_")
    return()
  endif()
  get_target_property(dir ${target} SOURCE_DIR)
  file(RELATIVE_PATH relative ${PROJECT_SOURCE_DIR}/plugins ${dir})
  if(relative MATCHES "^\\.\\." OR relative STREQUAL "")
    return()
  endif()
  string(REGEX REPLACE "/.*" "" plugin "${relative}")
  set(${out} ${plugin} PARENT_SCOPE)
endfunction()

# Every target `target` links, directly or through the libraries it links.
function(_trephine_links_of target out)
  set(seen "")
  set(pending ${target})
  while(pending)
    list(POP_FRONT pending current)
    get_target_property(aliased ${current} ALIASED_TARGET)
    if(aliased)
      set(current ${aliased})
    endif()
    set(links "")
    get_target_property(type ${current} TYPE)
    if(NOT type STREQUAL "INTERFACE_LIBRARY")
      get_target_property(direct ${current} LINK_LIBRARIES)
      if(direct)
        list(APPEND links ${direct})
      endif()
    endif()
    get_target_property(interface ${current} INTERFACE_LINK_LIBRARIES)
    if(interface)
      list(APPEND links ${interface})
    endif()
    foreach(link IN LISTS links)
      if(TARGET ${link} AND NOT link IN_LIST seen)
        list(APPEND seen ${link})
        list(APPEND pending ${link})
      endif()
    endforeach()
  endwhile()
  set(${out} ${seen} PARENT_SCOPE)
endfunction()

function(trephine_check_plugin_isolation)
  set(checked 0)
  foreach(folder IN LISTS ARGN)
    get_property(targets DIRECTORY ${PROJECT_SOURCE_DIR}/plugins/${folder} PROPERTY BUILDSYSTEM_TARGETS)
    foreach(target IN LISTS targets)
      _trephine_plugin_of(${target} owner)
      if(NOT owner STREQUAL folder)
        continue()
      endif()
      math(EXPR checked "${checked} + 1")
      _trephine_links_of(${target} links)
      foreach(link IN LISTS links)
        _trephine_plugin_of(${link} other)
        if(other AND NOT other STREQUAL folder)
          message(FATAL_ERROR "${target} (plugin '${folder}') links ${link}, a library of plugin '${other}': "
                              "plugins meet only through the framework's interfaces and the registry")
        endif()
      endforeach()
    endforeach()
  endforeach()
  # A check that found nothing to check proves nothing.
  if(checked EQUAL 0)
    message(FATAL_ERROR "trephine_check_plugin_isolation found no plugin library in: ${ARGN}")
  endif()
  set(TREPHINE_PLUGIN_LIBRARIES_CHECKED ${checked} CACHE INTERNAL "Plugin libraries whose links were checked")
endfunction()

# trephine_check_links_no_plugin(<target>)
#
# A program of the framework (bin/trephine) links no plugin's library,
# directly or through another: what a plugin gives it, it gets by loading the
# plugin (a registry service, such as PluginCommands). Checked when the build
# is configured, naming the library and its plugin.
function(trephine_check_links_no_plugin target)
  _trephine_links_of(${target} links)
  if(NOT links)
    message(FATAL_ERROR "trephine_check_links_no_plugin: ${target} links nothing this check can see")
  endif()
  foreach(link IN LISTS links)
    _trephine_plugin_of(${link} plugin)
    if(plugin)
      message(FATAL_ERROR "${target} links ${link}, a library of plugin '${plugin}': the program loads plugins "
                          "(a registry service, framework/runtime/PluginCommands.h), it does not link them")
    endif()
  endforeach()
endfunction()
