# Device primitives: benchmark (chunked kernels against Boost.Compute); and start-up cost.
# Both print their JSON with nlohmann::ordered_json, as btocl_bench does (scenes.cmake, included
# after this file, finds it again; a second find_package is a no-op).
find_package(nlohmann_json 3 REQUIRED)
foreach(prog bench_primitives startup)
  add_executable(${prog} "${CMAKE_CURRENT_LIST_DIR}/${prog}.cpp")
  btocl_target_defaults(${prog})
  # They reach past the public header, into the library's own classes and kernels.
  target_link_libraries(${prog} PRIVATE btocl_internal CLI11::CLI11 nlohmann_json::nlohmann_json)
endforeach()
target_link_libraries(startup PRIVATE btocl_scenes)  # its dropping scenes
