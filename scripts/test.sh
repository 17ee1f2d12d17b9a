#!/usr/bin/env bash
# Sets up, builds and runs the whole test suite on the default OpenCL device (PoCL's CPU here).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
cd build
ctest --output-on-failure -j 1 "$@"
