# CTest script: installs the build tree into BUILD_DIR/consumer-install, then configures, builds
# and runs tests/consumer against that prefix alone.
#   cmake -DBUILD_DIR=<build> -DSOURCE_DIR=<tests/consumer> -P run_consumer_test.cmake
set(prefix "${BUILD_DIR}/consumer-install")
set(work "${BUILD_DIR}/consumer-build")
file(REMOVE_RECURSE "${prefix}" "${work}")

function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}):\n${out}\n${err}")
  endif()
  set(last_output "${out}" PARENT_SCOPE)
endfunction()

run("install" "${CMAKE_COMMAND}" --install "${BUILD_DIR}" --prefix "${prefix}")
foreach(f include/BulletOpenCLSolver/btOpenCLConstraintSolver.h)
  if(NOT EXISTS "${prefix}/${f}")
    message(FATAL_ERROR "install did not give ${f}")
  endif()
endforeach()
run("configure the consumer" "${CMAKE_COMMAND}" -S "${SOURCE_DIR}" -B "${work}"
    -DCMAKE_BUILD_TYPE=Release "-DCMAKE_PREFIX_PATH=${prefix}")
run("build the consumer" "${CMAKE_COMMAND}" --build "${work}")
run("run the consumer" "${work}/consumer")
if(NOT last_output MATCHES "device: [^\n]+")
  message(FATAL_ERROR "the consumer printed no device name:\n${last_output}")
endif()
message(STATUS "${last_output}")
