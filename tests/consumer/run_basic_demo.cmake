# CTest script: runs examples/basic_demo and checks what it printed: our solver ran the steps,
# no box sank into the ground or flew off, and the heap stands about as high as five layers.
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
# The 5 x 5 x 5 array lands as a heap, which settles chaotically: after 5 s a box may still be
# sliding off it, with Bullet's solver as with ours (btocl_bench --scene basic, 600 steps: boxes
# still move in the last quarter with either solver, depending on the size), so the check asks
# for nothing a chaotic settling can miss. The lowest centre sits half a box (0.1 m) above the
# ground's top (y = 0), less a little penetration; the top box stays below the 1 m of five
# stacked layers and above the 0.3 m of a heap spread out; nothing moves as fast as a box
# dropped from the array's height hits the ground (about 7 m/s), which a box thrown about would.
if(NOT lowest GREATER 0.07)
  message(FATAL_ERROR "a box sank into the ground: lowest centre at y = ${lowest} m")
endif()
if(top LESS 0.3 OR top GREATER 1.0)
  message(FATAL_ERROR "the top box is not where a heap of five layers puts it: y = ${top} m")
endif()
if(NOT fastest LESS 5.0)
  message(FATAL_ERROR "a box was thrown about: fastest ${fastest} m/s")
endif()
