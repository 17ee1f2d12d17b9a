# Compile settings shared by every target of ours (library, demos, tests), in one place.
option(BTOCL_SANITIZE "Build with AddressSanitizer and UndefinedBehaviorSanitizer (UB stops the program)" OFF)
option(BTOCL_SANITIZE_THREAD "Build with ThreadSanitizer (scripts/test-threads-tsan.sh: the thread tests)" OFF)
if(BTOCL_SANITIZE AND BTOCL_SANITIZE_THREAD)
  message(FATAL_ERROR "BTOCL_SANITIZE and BTOCL_SANITIZE_THREAD cannot be on in one build")
endif()

# What links a sanitized library needs: the sanitizers' runtimes (the installed package passes it on,
# through the exported target and the pkg-config file alike).
set(BTOCL_SANITIZER_LINK_FLAG "")
if(BTOCL_SANITIZE)
  set(BTOCL_SANITIZER_LINK_FLAG -fsanitize=address,undefined)
elseif(BTOCL_SANITIZE_THREAD)
  set(BTOCL_SANITIZER_LINK_FLAG -fsanitize=thread)
endif()

function(btocl_target_defaults target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wno-ignored-attributes)
  # No fused multiply-adds whatever -march a build adds: the host's row math keeps the bits that a
  # CPU device's kernels compute (kernels/btocl_shared.h, BTOCL_NO_CONTRACTION).
  target_compile_options(${target} PRIVATE -ffp-contract=off)
  # Boost.Compute: stay within OpenCL 1.2, as the kernels do.
  target_compile_definitions(${target} PRIVATE BOOST_COMPUTE_MAX_CL_VERSION=102)
  if(BTOCL_SANITIZE)
    target_compile_options(${target} PRIVATE
      -fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer)
    # PUBLIC: whatever links a sanitized static library needs the sanitizers' runtimes too.
    target_link_options(${target} PUBLIC ${BTOCL_SANITIZER_LINK_FLAG})
  endif()
  if(BTOCL_SANITIZE_THREAD)
    target_compile_options(${target} PRIVATE -fsanitize=thread -fno-omit-frame-pointer)
    target_link_options(${target} PUBLIC ${BTOCL_SANITIZER_LINK_FLAG})
  endif()
endfunction()
