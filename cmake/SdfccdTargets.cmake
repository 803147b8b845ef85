# Target helpers shared by every sdfccd CMakeLists.

# Warning flags of every sdfccd target.
function(sdfccd_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow=local -Wno-unknown-pragmas)
endfunction()

# sdfccd_add_library(name DIR dir SOURCES src...): a library target sdfccd_<name> with alias sdfccd::<name>,
# exported for install. Sources are listed explicitly, relative to DIR/src (which is also a private include
# folder for the module's internal headers); public headers live in DIR/include and are installed.
function(sdfccd_add_library name)
  cmake_parse_arguments(arg "" "DIR" "SOURCES" ${ARGN})
  list(TRANSFORM arg_SOURCES PREPEND ${arg_DIR}/src/)
  if(SDFCCD_SYNTAX_CHECK)  # the root CMakeLists: each file compiled alone, nothing archived or installed
    add_library(sdfccd_${name} OBJECT ${arg_SOURCES})
  else()
    add_library(sdfccd_${name} ${arg_SOURCES})
  endif()
  add_library(sdfccd::${name} ALIAS sdfccd_${name})
  set_target_properties(sdfccd_${name} PROPERTIES EXPORT_NAME ${name} OUTPUT_NAME sdfccd_${name})
  target_include_directories(sdfccd_${name}
    PUBLIC $<BUILD_INTERFACE:${arg_DIR}/include> $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>
    PRIVATE ${arg_DIR}/src)
  sdfccd_set_warnings(sdfccd_${name})
  if(SDFCCD_SYNTAX_CHECK)
    return()
  endif()
  install(TARGETS sdfccd_${name} EXPORT sdfccdTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(DIRECTORY ${arg_DIR}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endfunction()
