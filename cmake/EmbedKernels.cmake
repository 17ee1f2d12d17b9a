# Embeds the OpenCL sources under kernels/ into a generated C++ source, so the library needs no
# file look-ups at run time. The generated file is rebuilt whenever a kernel file changes.
set(BTOCL_KERNEL_FILES
  arrange.cl batch.cl primitives.cl setup.cl solve.cl split.cl
  batch_priority.h btocl_shared.h lane_setup.h lane_solve.h row_setup.h row_solve.h split_grid.h vec_math.h)

function(btocl_embed_kernels out_cpp)
  set(kernel_files "")
  foreach(f IN LISTS BTOCL_KERNEL_FILES)
    list(APPEND kernel_files "${PROJECT_SOURCE_DIR}/kernels/${f}")
  endforeach()
  add_custom_command(
    OUTPUT "${out_cpp}"
    COMMAND "${CMAKE_COMMAND}" -DOUT=${out_cpp} "-DFILES=${kernel_files}"
            -P "${PROJECT_SOURCE_DIR}/cmake/WriteKernelSources.cmake"
    DEPENDS ${kernel_files} "${PROJECT_SOURCE_DIR}/cmake/WriteKernelSources.cmake"
    COMMENT "Embedding OpenCL kernel sources"
    VERBATIM)
endfunction()
