#!/usr/bin/env bash
# Sets up, builds and runs a small side-by-side demo: 1,000 boxes dropped into a pile, stepped
# 240 times (4 s of simulated time) with Bullet's btSequentialImpulseConstraintSolver in one
# world and btOpenCLConstraintSolver in an identical one, 10 iterations each. Prints the JSON
# summary (timings per solver and per phase, counts, quality) and draws the last frame to
# build/demo_pile.png (SI left, ours right, each panel labelled with its solver's name). Extra
# arguments go to btocl_bench.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh >&2
bash scripts/build.sh >&2
exec build/demos/btocl_bench --scene pile --size 1000 --steps 240 --iterations 10 \
  --png build/demo_pile.png "$@"
