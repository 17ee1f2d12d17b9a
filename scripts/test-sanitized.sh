#!/usr/bin/env bash
# Builds the library and the tests with AddressSanitizer and UndefinedBehaviorSanitizer
# (BTOCL_SANITIZE) into build-asan/ and runs them there: a memory error, a leak or undefined
# behaviour in our code fails the run. Debug: it builds in about a third of the time of an
# optimised build, and the tests spend most of their time in the OpenCL driver anyway. The
# demos are left out; install_and_consume builds its consumers with the same flags (the
# installed package passes them on, through CMake and pkg-config), and the shared library
# sanitized too.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DBTOCL_SANITIZE=ON -DBTOCL_BUILD_DEMOS=OFF >/dev/null
cmake --build build-asan -j "$(nproc)"
cd build-asan
ctest --output-on-failure -j "$(nproc)" "$@"
