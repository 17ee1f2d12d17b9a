# CTest script: runs examples/basic_demo and checks what it printed: our solver ran every step,
# and the boxes came to rest, stacked, on the ground.
#   cmake -DDEMO=<basic_demo executable> -P run_basic_demo.cmake
execute_process(COMMAND "${DEMO}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message(STATUS "${out}${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "basic_demo failed (${rc})")
endif()
if(NOT out MATCHES "solver: btOpenCLConstraintSolver ")
  message(FATAL_ERROR "basic_demo ran without our solver")
endif()
if(NOT out MATCHES "solved on the (device|host)")
  message(FATAL_ERROR "basic_demo's last step was not solved by our solver")
endif()
set(number "(-?[0-9]+\\.[0-9]+)")
if(NOT out MATCHES "top box at y = ${number} m, lowest box at y = ${number} m, fastest box ${number} m/s")
  message(FATAL_ERROR "basic_demo printed no heights")
endif()
set(top "${CMAKE_MATCH_1}")
set(lowest "${CMAKE_MATCH_2}")
set(fastest "${CMAKE_MATCH_3}")
# Five layers of boxes 0.2 m high rest with their centres at 0.1 to 0.9 m: the lowest above the
# ground's top (y = 0) by half a box, less a little penetration; the top one near 0.9 m, lower if
# the stack fell apart or sank, higher if boxes are still in the air. After 5 s a few boxes at the
# pile's edge still creep at a few cm/s (with Bullet's solver too); one still falling or thrown
# about moves faster.
if(NOT lowest GREATER 0.07)
  message(FATAL_ERROR "a box sank into the ground: lowest centre at y = ${lowest} m")
endif()
if(top LESS 0.8 OR top GREATER 1.0)
  message(FATAL_ERROR "the top box is not where five layers put it: y = ${top} m")
endif()
if(NOT fastest LESS 0.2)
  message(FATAL_ERROR "the boxes are not at rest: fastest ${fastest} m/s")
endif()
