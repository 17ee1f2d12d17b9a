# Compile settings shared by every target of ours (library, demos, tests), in one place.
function(btocl_target_defaults target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wno-ignored-attributes)
  # Boost.Compute: stay within OpenCL 1.2, as the kernels do.
  target_compile_definitions(${target} PRIVATE BOOST_COMPUTE_MAX_CL_VERSION=102)
endfunction()
