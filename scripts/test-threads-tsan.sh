#!/usr/bin/env bash
# Builds the library and the thread tests (tests/test_threads.cpp: solvers made and stepped in
# threads at once, on both solve paths and through the fallback) with ThreadSanitizer into
# build-tsan/ and runs them: a data race in our code, or in the header-only libraries compiled into
# it (Boost.Compute), fails the run at its first report. The OpenCL driver and Bullet are not
# instrumented: their own accesses are not seen, the locks they take are. Debug, as the ASan build.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake -S . -B build-tsan -DCMAKE_BUILD_TYPE=Debug -DBTOCL_SANITIZE_THREAD=ON -DBTOCL_BUILD_DEMOS=OFF >/dev/null
cmake --build build-tsan -j "$(nproc)" --target btocl_thread_tests
BT_OPENCL_DEVICE=cpu TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1 ${TSAN_OPTIONS:-}" \
  build-tsan/tests/btocl_thread_tests "$@"
