#!/usr/bin/env bash
# How cost grows with the scene: block and columns at 3K, 12K and 48K boxes, each solver in a
# process of its own (btocl_bench --solver si, then --solver ocl), so that the process's peak
# resident memory is that solver's world and solver alone. Prints a Markdown table: contact
# points, solver ms per step (median) and per 1,000 contact points (median over the steps), peak
# RSS of each process, and our device bytes per contact point. The JSON files stay in
# build/growth/. About 5 minutes a round on 2 cores.
#
#   bash scripts/growth.sh                  # every run below, three rounds
#   bash scripts/growth.sh block            # only the runs of one scene
#   bash scripts/growth.sh --rounds 1 [SCENE]
#
# Rounds: each round runs every size with both solvers, SI first in odd rounds and ours first in
# even ones, so that a slow minute of this VM falls on both sides; the table takes each size's
# median over the rounds, and its ratio is the median of the rounds' ratios (two runs of one
# round each, taken minutes apart, differed by up to 2x on single rows).
#
# Steps: block stands, so a few steps measure it (the 48K block holds 1.2M contact points and
# costs Bullet's solver about 1.3 s a step here, plus about 2 s for collision detection), but
# enough that the first ones stay out of the median: ours' first 48K step writes its arrays for
# the first time (about 1 s; the second did too until its arrays kept room to spare) and its
# first steps time the device's and the host's ways by turns, so the 48K block runs 12
# (docs/performance.md, "How cost grows");
# columns change through the run (standing columns, then the collapse, then a pile), so every
# size runs the same 150 steps (2.5 s: the columns fall; the 48K run's collision detection alone
# takes about 0.7 s a step here) and is compared per contact point.
# On a CPU device (PoCL) the device's buffers are host memory: ours' RSS includes deviceBytes.
set -euo pipefail
cd "$(dirname "$0")/.."
rounds=3
if [[ "${1:-}" == "--rounds" ]]; then
  rounds="${2:?--rounds needs a count}"
  shift 2
fi
[[ "$rounds" =~ ^[1-9][0-9]*$ ]] || { echo "growth.sh: --rounds takes a positive count, not '$rounds'" >&2; exit 2; }
only="${1:-}"
bash scripts/setup.sh
bash scripts/build.sh >/dev/null
bench=build/demos/btocl_bench
mkdir -p build/growth
# One run a folder (scripts/record-bench.sh keeps it whole): no earlier round's files left.
rm -f build/growth/${only:+$only-}*.json
runs=(
  "block 3000 30"
  "block 12000 20"
  "block 48000 12"
  "columns 3000 150"
  "columns 12000 150"
  "columns 48000 150"
)
names=()
for run in "${runs[@]}"; do
  read -r scene size steps <<<"$run"
  if [[ -n "$only" && "$scene" != "$only" ]]; then continue; fi
  names+=("$scene-$size")
done
# Round 1's files are NAME-si.json and NAME-ocl.json; round r's NAME-si.r.json and NAME-ocl.r.json.
for ((round = 1; round <= rounds; ++round)); do
  order=(si ocl)
  (( round % 2 == 0 )) && order=(ocl si)
  suffix=""
  (( round > 1 )) && suffix=".$round"
  for run in "${runs[@]}"; do
    read -r scene size steps <<<"$run"
    if [[ -n "$only" && "$scene" != "$only" ]]; then continue; fi
    # PoCL compiles a kernel variant the first time it meets a launch shape (then caches it).
    if [[ "$round" -eq 1 && "$size" -le 3000 ]]; then
      "$bench" --scene "$scene" --size "$size" --steps 3 --solver ocl >/dev/null 2>&1 || true
    fi
    for solver in "${order[@]}"; do
      echo "== round $round of $rounds: $scene (size $size, $steps steps), --solver $solver" >&2
      "$bench" --scene "$scene" --size "$size" --steps "$steps" --solver "$solver" \
        --json "build/growth/$scene-$size-$solver$suffix.json" >/dev/null
    done
  done
done
python3 scripts/perf_report.py growth build/growth "${names[@]}"
