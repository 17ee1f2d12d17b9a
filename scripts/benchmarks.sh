#!/usr/bin/env bash
# Sets up, builds and runs the side-by-side benchmark on every scene, then prints its
# results table (Markdown) from the JSON summaries. The JSON files stay in build/bench/.
# Each scene first runs a few steps of our solver alone: PoCL compiles kernel variants the first
# time it meets a launch shape and caches them, and that one-time cost is not a step's cost.
#
#   bash scripts/benchmarks.sh                      # speed: every scene, a table (record-bench.sh keeps it)
#   bash scripts/benchmarks.sh --quality [RUN...]   # quality of resting scenes, 600 steps each
#
# --quality runs scenes that come to rest (a pyramid with a base of 20, the default wall, a
# small dense block of 216 boxes face to face, a pile of 1,000 dropped boxes) for 600 steps (10 s)
# and prints, for SI, SI with its order randomized (SOLVER_RANDMIZE_ORDER), ours as it ships
# (SI's fixed order), ours with SOLVER_RANDMIZE_ORDER and ours with rotatePoints: the largest
# drift (from the start for scenes that start at rest, else from step 450), the resting kinetic
# energy (mean of the last 150 steps), the deepest penetration and whether the stacks stand. RUN, "scene size" each, replaces the scenes.
# The JSON files stay in build/quality/.
set -euo pipefail
cd "$(dirname "$0")/.."
mode=speed
if [[ "${1:-}" == "--quality" ]]; then
  mode=quality
  shift
fi
bash scripts/setup.sh
bash scripts/build.sh >/dev/null
bench=build/demos/btocl_bench

if [[ "$mode" == quality ]]; then
  mkdir -p build/quality
  rm -f build/quality/*.json  # one run a folder: scripts/record-bench.sh keeps it whole
  runs=("$@")
  if [[ ${#runs[@]} -eq 0 ]]; then
    runs=("pyramid 20" "wall 10" "block-grid 216" "pile 1000")
  fi
  names=()
  for run in "${runs[@]}"; do
    read -r scene size <<<"$run"
    echo "== $scene (size $size, 600 steps)" >&2
    # SI, SI randomized and ours (as shipped) side by side; then ours randomized, and ours with
    # rotatePoints, each alone.
    "$bench" --scene "$scene" --size "$size" --steps 600 --with-si-randomized --order fixed \
      --json "build/quality/$scene-$size.json" >/dev/null
    "$bench" --scene "$scene" --size "$size" --steps 600 --solver ocl --order randomized \
      --json "build/quality/$scene-$size-randomized.json" >/dev/null
    "$bench" --scene "$scene" --size "$size" --steps 600 --solver ocl --order rotated \
      --json "build/quality/$scene-$size-rotated.json" >/dev/null
    names+=("$scene-$size")
  done
  python3 scripts/perf_report.py quality build/quality "${names[@]}"
  exit 0
fi

mkdir -p build/bench
rm -f build/bench/*.json  # one run a folder: scripts/record-bench.sh keeps it whole
# scene, size, steps: a new user's first scenes (Bullet's BasicDemo, a hinge chain, small stacks),
# then larger ones up to the paper's.
runs=(
  "basic 5 300"
  "chain 20 300"
  "pyramid 10 300"
  "pyramid 20 300"
  "wall 10 300"
  "pile 1000 300"
  "pyramid3d 20 150"
  "ragdolls 200 600"
  "machine 64 600"
  "columns 12000 300"
  "block 12000 30"
)
names=()
for run in "${runs[@]}"; do
  read -r scene size steps <<<"$run"
  echo "== $scene (size $size, $steps steps)" >&2
  "$bench" --scene "$scene" --size "$size" --steps 8 --solver ocl >/dev/null 2>&1 || true
  "$bench" --scene "$scene" --size "$size" --steps "$steps" --iterations 10 --json "build/bench/$scene-$size.json" >/dev/null
  names+=("$scene-$size")
done
python3 scripts/perf_report.py speed build/bench
