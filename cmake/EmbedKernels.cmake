# Embeds every file under kernels/ into a generated C++ source, so the library needs no
# file look-ups at run time. The generated file is rebuilt whenever a kernel file changes.
function(btocl_embed_kernels out_cpp)
  file(GLOB kernel_files CONFIGURE_DEPENDS
       "${PROJECT_SOURCE_DIR}/kernels/*.cl" "${PROJECT_SOURCE_DIR}/kernels/*.h")
  add_custom_command(
    OUTPUT "${out_cpp}"
    COMMAND "${CMAKE_COMMAND}" -DOUT=${out_cpp} "-DFILES=${kernel_files}"
            -P "${PROJECT_SOURCE_DIR}/cmake/WriteKernelSources.cmake"
    DEPENDS ${kernel_files} "${PROJECT_SOURCE_DIR}/cmake/WriteKernelSources.cmake"
    COMMENT "Embedding OpenCL kernel sources"
    VERBATIM)
endfunction()
