#!/usr/bin/env bash
# Sets up, builds and runs the whole test suite on the default OpenCL device (PoCL's CPU here).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
cd build
# One test per core: a test spends much of its time starting PoCL or compiling, one thread.
ctest --output-on-failure -j "$(nproc)" "$@"
