# Installs the build tree into WORK_DIR/prefix, then configures, builds and runs two projects against that
# prefix alone: the consumer (every exported target; a Bullet world) and demos/examples (hello_world, whose
# report of contacts and of the bunnies not falling through the cylinder and the ramp is checked, and drop_bunny,
# the README's example, run from the repository root as the README says). Inputs: BUILD_DIR, SOURCE_DIR
# (tests/consumer), EXAMPLES_DIR, ASSETS_DIR, WORK_DIR.
file(REMOVE_RECURSE ${WORK_DIR})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${WORK_DIR}/prefix
                RESULT_VARIABLE rc OUTPUT_QUIET)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cmake --install failed (${rc})")
endif()

# Configures and builds the project in `source` against the prefix, in WORK_DIR/`name`.
function(build_against_prefix name source)
  execute_process(COMMAND ${CMAKE_COMMAND} -S ${source} -B ${WORK_DIR}/${name} -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix
                          -DCMAKE_BUILD_TYPE=Release -DSDFCCD_ASSETS_DIR=${ASSETS_DIR} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "configuring ${name} against the installed sdfccd failed (${rc})")
  endif()
  execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK_DIR}/${name} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "building ${name} against the installed sdfccd failed (${rc})")
  endif()
endfunction()

build_against_prefix(consumer ${SOURCE_DIR})
execute_process(COMMAND ${WORK_DIR}/consumer/consumer RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the consumer failed (${rc})")
endif()

build_against_prefix(examples ${EXAMPLES_DIR})
execute_process(COMMAND ${WORK_DIR}/examples/hello_world ${ASSETS_DIR}/meshes/bunny.off RESULT_VARIABLE rc
                OUTPUT_VARIABLE out)
message("${out}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "hello_world failed (${rc})")
endif()
# Every pair kind of the example: bunny-ground (plane), bunny-bunny, Bullet's own box-ground, a bunny on a
# btCylinderShape and one on the static btBvhTriangleMeshShape ramp.
foreach(expected "bunny-1 touched ground" "bunny-1 touched bunny-2" "box touched ground"
                 "bunny-on-cylinder touched cylinder" "bunny-on-ramp touched ramp"
                 # and neither supported bunny fell through its support (no shell point a cell deep inside the
                 # cylinder; the bunny's centre never crossed the ramp's sheet); only touching points count as
                 # touches. Both bunnies tip off their narrow supports and land beside them: that is not checked.
                 "bunny-on-cylinder did not fall through cylinder" "bunny-on-ramp did not fall through ramp")
  string(FIND "${out}" "${expected}" found)
  if(found EQUAL -1)
    message(FATAL_ERROR "hello_world did not report \"${expected}\"")
  endif()
endforeach()

# The README's example: it reads assets/meshes/bunny.off relative to the repository root and prints where the bunny
# rests.
get_filename_component(repository_root ${ASSETS_DIR} DIRECTORY)
execute_process(COMMAND ${WORK_DIR}/examples/drop_bunny WORKING_DIRECTORY ${repository_root} RESULT_VARIABLE rc
                OUTPUT_VARIABLE out)
message("${out}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "drop_bunny failed (${rc})")
endif()
if(NOT out MATCHES "the bunny rests at y = [0-9.]+ m")
  message(FATAL_ERROR "drop_bunny did not report where the bunny rests")
endif()
