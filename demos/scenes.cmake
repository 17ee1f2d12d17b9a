# Side-by-side benchmark of Bullet's sequential-impulse solver and ours on headless scenes
# (demos/bench/), with a PNG picture of a chosen frame.
find_package(PNG REQUIRED)
find_package(nlohmann_json 3 REQUIRED)

add_executable(btocl_bench
  bench/btocl_bench.cpp
  bench/BenchOptions.cpp
  bench/BenchSummary.cpp
  bench/BitmapFont.cpp
  bench/PngFile.cpp
  bench/Quality.cpp
  bench/Raster.cpp
  bench/ScenePicture.cpp
  bench/Scenes.cpp
  bench/SolverSide.cpp
  bench/TimedSolver.cpp)
btocl_target_defaults(btocl_bench)
target_include_directories(btocl_bench PRIVATE "${CMAKE_CURRENT_SOURCE_DIR}")  # CliChecks.h, shared with the other demos
target_link_libraries(btocl_bench PRIVATE btocl_scenes bullet_opencl_solver PNG::PNG nlohmann_json::nlohmann_json CLI11::CLI11)

if(BTOCL_BUILD_TESTS)
  set(BTOCL_BENCH_SCENES pyramid stack wall pile columns block block-grid ragdolls machine basic pyramid3d chain)
  # One smoke run per scene (the joint scenes too): small, 20 steps, both solvers side by side,
  # split and batch invariants checked every step; an error of our solver fails the test.
  foreach(scene IN LISTS BTOCL_BENCH_SCENES)
    add_test(NAME bench_smoke_${scene} COMMAND btocl_bench --scene ${scene} --smoke --validate)
    list(APPEND BTOCL_BENCH_TESTS bench_smoke_${scene})
  endforeach()
  # The harness itself: with Bullet's solver on both sides the two worlds must stay identical
  # (a scene builder with hidden state, or worlds sharing anything, would make them part).
  add_test(NAME bench_harness_identical_worlds
           COMMAND btocl_bench --scene pile --smoke --stand-in --max-divergence 0)
  # A picture of a frame, through the rasteriser and libpng.
  add_test(NAME bench_png
           COMMAND btocl_bench --scene pyramid --smoke --frame 10
                   --png "${CMAKE_CURRENT_BINARY_DIR}/bench_smoke_pyramid.png")
  # The third world, Bullet's solver with its order randomized, stepped beside the two.
  add_test(NAME bench_si_randomized COMMAND btocl_bench --scene wall --smoke --validate --with-si-randomized)
  list(APPEND BTOCL_BENCH_TESTS bench_harness_identical_worlds bench_png bench_si_randomized)
  set_tests_properties(${BTOCL_BENCH_TESTS} PROPERTIES ENVIRONMENT "BT_OPENCL_DEVICE=cpu")

  # Bad input gets a clear message (checked) rather than a crash.
  add_test(NAME bench_rejects_unknown_scene COMMAND btocl_bench --scene no-such-scene)
  set_tests_properties(bench_rejects_unknown_scene PROPERTIES PASS_REGULAR_EXPRESSION "unknown scene 'no-such-scene'")
  add_test(NAME bench_rejects_bad_number COMMAND btocl_bench --scene pyramid --steps -3)
  set_tests_properties(bench_rejects_bad_number PROPERTIES PASS_REGULAR_EXPRESSION "--steps: '-3' is not an integer in \\[0, 1000000\\]")
endif()
