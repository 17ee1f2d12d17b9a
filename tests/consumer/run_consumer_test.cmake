# CTest script: the installed package, used as a user would, for both kinds of library. The build
# tree under test is installed as it is; the other kind (static or shared) is built from SOURCE
# with the library alone, in a build folder kept between runs. Against each install prefix:
#   - tests/consumer built with CMake (find_package) and with a plain compiler command line
#     (pkg-config bullet-opencl-solver), and each run;
#   - the package's version file refuses another minor or major version (static install);
#   - examples/ built on its own and basic_demo run and checked (shared install).
#   cmake -DBUILD_DIR=<build> -DSOURCE=<project source> -DSHARED=<BUILD_SHARED_LIBS of the build>
#         -DVERSION=<project version> -DLIBDIR=<CMAKE_INSTALL_LIBDIR> -DCONFIG=<build type>
#         -DSANITIZE=<BTOCL_SANITIZE> -DSANITIZE_THREAD=<BTOCL_SANITIZE_THREAD> -DCXX=<compiler>
#         -DPKG_CONFIG=<pkg-config> -DREADELF=<readelf> -DNM=<nm> -P run_consumer_test.cmake
set(work "${BUILD_DIR}/install-test")
set(consumer_source "${SOURCE}/tests/consumer")

function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}):\n${out}\n${err}")
  endif()
  set(last_output "${out}" PARENT_SCOPE)
endfunction()

# Times each stage, for the log: the install test is one of the suite's longest.
string(TIMESTAMP started "%s")
function(done what)
  string(TIMESTAMP now "%s")
  math(EXPR seconds "${now} - ${started}")
  message(STATUS "[${seconds} s] ${what}")
endfunction()

# The consumer's output: the headers' version, and a device (the solver was made).
string(REPLACE "." "\\." version_re "${VERSION}")
function(check_consumer_output what)
  if(NOT last_output MATCHES "version: ${version_re} \\(${version_re}\\)\n")
    message(FATAL_ERROR "${what}: the headers are not version ${VERSION}:\n${last_output}")
  endif()
  if(NOT last_output MATCHES "device: [^\n]+")
    message(FATAL_ERROR "${what}: no device name:\n${last_output}")
  endif()
endfunction()

# A program linked to the shared library names its soname.
function(check_links_soname what program)
  if(READELF)
    run("readelf ${program}" "${READELF}" -d "${program}")
    if(NOT last_output MATCHES "NEEDED[^\n]*libbullet_opencl_solver\\.so\\.0\\.1")
      message(FATAL_ERROR "${what} does not load libbullet_opencl_solver.so.0.1:\n${last_output}")
    endif()
  endif()
endfunction()

if(SHARED)
  set(this_kind shared)
  set(other_kind static)
  set(other_shared OFF)
else()
  set(this_kind static)
  set(other_kind shared)
  set(other_shared ON)
endif()

# The other kind, the library alone; not in a sanitized build, whose run checks that the package
# passes its flags on: the unsanitized run covers both kinds, and this build's kind is enough
# here (a second sanitized Debug library took a minute of CI's time).
set(build_of_${this_kind} "${BUILD_DIR}")
set(kinds static shared)
if(SANITIZE OR SANITIZE_THREAD)
  set(kinds ${this_kind})
else()
  set(other_build "${work}/${other_kind}-build")
  run("configure the ${other_kind} library" "${CMAKE_COMMAND}" -S "${SOURCE}" -B "${other_build}"
      "-DCMAKE_BUILD_TYPE=${CONFIG}" "-DCMAKE_CXX_COMPILER=${CXX}" "-DCMAKE_INSTALL_LIBDIR=${LIBDIR}"
      "-DBUILD_SHARED_LIBS=${other_shared}"
      "-DBTOCL_SANITIZE=${SANITIZE}" "-DBTOCL_SANITIZE_THREAD=${SANITIZE_THREAD}"
      -DBTOCL_BUILD_TESTS=OFF -DBTOCL_BUILD_DEMOS=OFF -DBTOCL_BUILD_EXAMPLES=OFF)
  run("build the ${other_kind} library" "${CMAKE_COMMAND}" --build "${other_build}" --parallel 2)
  done("${other_kind} library built")
  set(build_of_${other_kind} "${other_build}")
endif()

list(GET kinds 0 first_kind)
list(GET kinds -1 last_kind)
foreach(kind IN LISTS kinds)
  set(prefix "${work}/${kind}-install")
  set(libdir "${prefix}/${LIBDIR}")
  file(REMOVE_RECURSE "${prefix}" "${work}/${kind}-consumer" "${work}/${kind}-pkg-config")
  run("install the ${kind} library" "${CMAKE_COMMAND}" --install "${build_of_${kind}}" --prefix "${prefix}")

  set(files
    include/BulletOpenCLSolver/btOpenCLConstraintSolver.h include/BulletOpenCLSolver/btOpenCLSolverError.h
    include/BulletOpenCLSolver/btOpenCLSolverExport.h include/BulletOpenCLSolver/btOpenCLSolverVersion.h
    ${LIBDIR}/cmake/BulletOpenCLSolver/BulletOpenCLSolverConfig.cmake
    ${LIBDIR}/cmake/BulletOpenCLSolver/BulletOpenCLSolverConfigVersion.cmake
    ${LIBDIR}/pkgconfig/bullet-opencl-solver.pc)
  if(kind STREQUAL "static")
    list(APPEND files ${LIBDIR}/libbullet_opencl_solver.a)
  else()
    list(APPEND files ${LIBDIR}/libbullet_opencl_solver.so ${LIBDIR}/libbullet_opencl_solver.so.0.1
                      ${LIBDIR}/libbullet_opencl_solver.so.${VERSION})
  endif()
  foreach(f IN LISTS files)
    if(NOT EXISTS "${prefix}/${f}")
      message(FATAL_ERROR "the ${kind} install did not give ${f}")
    endif()
  endforeach()
  if(kind STREQUAL "shared" AND NM)
    # The public API exported, the library's own classes (namespace btocl) hidden.
    run("nm the shared library" "${NM}" -DC --defined-only "${libdir}/libbullet_opencl_solver.so")
    if(NOT last_output MATCHES "btOpenCLConstraintSolver::btOpenCLConstraintSolver\\(btOpenCLSolverConfig const&\\)")
      message(FATAL_ERROR "the shared library does not export btOpenCLConstraintSolver:\n${last_output}")
    endif()
    if(last_output MATCHES "btocl::")
      message(FATAL_ERROR "the shared library exports its internals:\n${last_output}")
    endif()
  endif()

  # With CMake: find_package and the exported target.
  set(consumer "${work}/${kind}-consumer")
  run("configure the ${kind} consumer" "${CMAKE_COMMAND}" -S "${consumer_source}" -B "${consumer}"
      "-DCMAKE_BUILD_TYPE=${CONFIG}" "-DCMAKE_CXX_COMPILER=${CXX}" "-DCMAKE_PREFIX_PATH=${prefix}")
  run("build the ${kind} consumer" "${CMAKE_COMMAND}" --build "${consumer}")
  run("run the ${kind} consumer" "${consumer}/consumer")
  check_consumer_output("the ${kind} consumer")
  if(kind STREQUAL "shared")
    check_links_soname("the shared consumer" "${consumer}/consumer")
  endif()
  done("${kind}: consumer built with CMake and run: ${last_output}")

  # With pkg-config and the compiler alone; --static for the static library (OpenCL, threads).
  set(ENV{PKG_CONFIG_PATH} "${libdir}/pkgconfig")
  run("pkg-config --modversion" "${PKG_CONFIG}" --modversion bullet-opencl-solver)
  if(NOT last_output STREQUAL "${VERSION}\n")
    message(FATAL_ERROR "pkg-config gives version ${last_output}, not ${VERSION}")
  endif()
  set(static_flag "")
  set(rpath "")
  if(kind STREQUAL "static")
    set(static_flag --static)
  else()
    set(rpath "-Wl,-rpath,${libdir}")
  endif()
  run("pkg-config --cflags --libs" "${PKG_CONFIG}" ${static_flag} --cflags --libs bullet-opencl-solver)
  separate_arguments(pc_flags UNIX_COMMAND "${last_output}")
  file(MAKE_DIRECTORY "${work}/${kind}-pkg-config")
  set(program "${work}/${kind}-pkg-config/consumer")
  run("build the ${kind} consumer with pkg-config" "${CXX}" -std=c++17 -o "${program}"
      "${consumer_source}/main.cpp" ${pc_flags} ${rpath})
  run("run the ${kind} consumer built with pkg-config" "${program}")
  check_consumer_output("the ${kind} consumer built with pkg-config")
  if(kind STREQUAL "shared")
    check_links_soname("the shared consumer built with pkg-config" "${program}")
  endif()
  string(REPLACE ";" " " pc_flags "${pc_flags}")
  done("${kind}: consumer built with pkg-config (${pc_flags}) and run")
  unset(ENV{PKG_CONFIG_PATH})
endforeach()

# SameMinorVersion: 0.1 is found (above); another minor or major version is refused by the
# package's version file, before its targets are read. 0.0 is the one that SameMajorVersion would
# take: a newer minor version of 0.x may have broken the API.
foreach(requested 0.0 0.2 1.0)
  set(refused "${work}/consumer-${requested}")
  execute_process(COMMAND "${CMAKE_COMMAND}" -S "${consumer_source}" -B "${refused}"
      "-DCMAKE_CXX_COMPILER=${CXX}" "-DCMAKE_PREFIX_PATH=${work}/${first_kind}-install"
      "-DBTOCL_REQUESTED_VERSION=${requested}"
    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  file(REMOVE_RECURSE "${refused}")
  # CMake wraps its message: any white space between the words.
  string(REPLACE "." "\\." requested_re "${requested}")
  if(rc EQUAL 0 OR NOT err MATCHES "compatible[ \n]+with[ \n]+requested[ \n]+version[ \n]+\"${requested_re}\"")
    message(FATAL_ERROR "find_package(BulletOpenCLSolver ${requested}) was not refused for its version (${rc}):\n${out}\n${err}")
  endif()
endforeach()
done("find_package(BulletOpenCLSolver 0.0), (0.2) and (1.0) refused")

# examples/ on its own, against the shared install (this build's kind where only it is installed).
set(examples "${work}/examples")
file(REMOVE_RECURSE "${examples}")
run("configure examples/" "${CMAKE_COMMAND}" -S "${SOURCE}/examples" -B "${examples}"
    "-DCMAKE_BUILD_TYPE=${CONFIG}" "-DCMAKE_CXX_COMPILER=${CXX}" "-DCMAKE_PREFIX_PATH=${work}/${last_kind}-install")
run("build examples/" "${CMAKE_COMMAND}" --build "${examples}")
if(last_kind STREQUAL "shared")
  check_links_soname("basic_demo" "${examples}/basic_demo")
endif()
run("run basic_demo" "${CMAKE_COMMAND}" "-DDEMO=${examples}/basic_demo" -P "${consumer_source}/run_basic_demo.cmake")
done("examples/ built on its own against the ${last_kind} install, basic_demo run and checked:\n${last_output}")
