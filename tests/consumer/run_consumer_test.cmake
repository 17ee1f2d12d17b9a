# CTest script: installs the build tree into BUILD_DIR/consumer-install, then configures, builds
# and runs tests/consumer against that prefix alone, and checks that the package refuses a version
# of another minor or major version.
#   cmake -DBUILD_DIR=<build> -DSOURCE_DIR=<tests/consumer> -DVERSION=<project version>
#         -P run_consumer_test.cmake
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
foreach(f btOpenCLConstraintSolver.h btOpenCLSolverError.h btOpenCLSolverExport.h btOpenCLSolverVersion.h)
  set(f "include/BulletOpenCLSolver/${f}")
  if(NOT EXISTS "${prefix}/${f}")
    message(FATAL_ERROR "install did not give ${f}")
  endif()
endforeach()
run("configure the consumer" "${CMAKE_COMMAND}" -S "${SOURCE_DIR}" -B "${work}"
    -DCMAKE_BUILD_TYPE=Release "-DCMAKE_PREFIX_PATH=${prefix}")
run("build the consumer" "${CMAKE_COMMAND}" --build "${work}")
run("run the consumer" "${work}/consumer")
string(REPLACE "." "\\." version_re "${VERSION}")
if(NOT last_output MATCHES "version: ${version_re} \\(${version_re}\\)\n")
  message(FATAL_ERROR "the consumer's headers are not version ${VERSION}:\n${last_output}")
endif()
if(NOT last_output MATCHES "device: [^\n]+")
  message(FATAL_ERROR "the consumer printed no device name:\n${last_output}")
endif()
message(STATUS "${last_output}")

# SameMinorVersion: 0.1 is found (above); another minor or major version is refused by the
# package's version file, before its targets are read. 0.0 is the one that SameMajorVersion would
# take: a newer minor version of 0.x may have broken the API.
foreach(requested 0.0 0.2 1.0)
  execute_process(COMMAND "${CMAKE_COMMAND}" -S "${SOURCE_DIR}" -B "${work}-${requested}"
      "-DCMAKE_PREFIX_PATH=${prefix}" "-DBTOCL_REQUESTED_VERSION=${requested}"
    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  # CMake wraps its message: any white space between the words.
  string(REPLACE "." "\\." requested_re "${requested}")
  if(rc EQUAL 0 OR NOT err MATCHES "compatible[ \n]+with[ \n]+requested[ \n]+version[ \n]+\"${requested_re}\"")
    message(FATAL_ERROR "find_package(BulletOpenCLSolver ${requested}) was not refused for its version (${rc}):\n${out}\n${err}")
  endif()
  file(REMOVE_RECURSE "${work}-${requested}")
  message(STATUS "find_package(BulletOpenCLSolver ${requested}) refused, as it should be")
endforeach()
