# Warning flags shared by every sdfccd target.
function(sdfccd_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow=local -Wno-unknown-pragmas)
endfunction()

# Adds a library target named sdfccd_<name> with alias sdfccd::<name>, exported for install.
# Sources: every .cpp below DIR/src; public headers: DIR/include.
function(sdfccd_add_library name dir)
  file(GLOB_RECURSE sources CONFIGURE_DEPENDS ${dir}/src/*.cpp)
  if(NOT sources)
    message(STATUS "sdfccd::${name}: no sources yet, not built")
    return()
  endif()
  add_library(sdfccd_${name} ${sources})
  add_library(sdfccd::${name} ALIAS sdfccd_${name})
  set_target_properties(sdfccd_${name} PROPERTIES EXPORT_NAME ${name} OUTPUT_NAME sdfccd_${name})
  target_include_directories(sdfccd_${name} PUBLIC
    $<BUILD_INTERFACE:${dir}/include> $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  sdfccd_set_warnings(sdfccd_${name})
  install(TARGETS sdfccd_${name} EXPORT sdfccdTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(DIRECTORY ${dir}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endfunction()
