# Device primitives: benchmark (chunked kernels against Boost.Compute) and start-up cost.
foreach(prog bench_primitives startup)
  add_executable(${prog} "${CMAKE_CURRENT_LIST_DIR}/${prog}.cpp")
  target_include_directories(${prog} PRIVATE "${PROJECT_SOURCE_DIR}/bullet_plugin" "${PROJECT_SOURCE_DIR}/kernels")
  target_compile_definitions(${prog} PRIVATE BOOST_COMPUTE_MAX_CL_VERSION=102)
  target_compile_options(${prog} PRIVATE -Wall -Wextra -Wno-ignored-attributes)
  target_link_libraries(${prog} PRIVATE bullet_opencl_solver OpenCL::OpenCL Boost::headers)
endforeach()
