#!/usr/bin/env bash
# Sets up, builds and runs the side-by-side benchmark on every scene, then prints the README's
# results table (Markdown) from the JSON summaries. The JSON files stay in build/bench/.
# Each scene first runs a few steps of our solver alone: PoCL compiles kernel variants the first
# time it meets a launch shape and caches them, and that one-time cost is not a step's cost.
#
#   bash scripts/benchmarks.sh                      # speed: the README's results table
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
  python3 - build/quality "${names[@]}" <<'PY'
import json, os, sys
folder, names = sys.argv[1], sys.argv[2:]
print("| scene | bodies | solver | max drift | resting kinetic energy | max penetration | standing |")
print("|---|---|---|---|---|---|---|")
def yn(v):
    return "-" if v is None else ("yes" if v else "no")
for name in names:
    both = json.load(open(os.path.join(folder, name + ".json")))
    randomized = json.load(open(os.path.join(folder, name + "-randomized.json")))
    rotated = json.load(open(os.path.join(folder, name + "-rotated.json")))
    sides = [("SI", both["si"]), ("SI randomized", both["siRandomized"]), ("ours", both["ours"]),
             ("ours randomized", randomized["ours"]), ("ours, rotatePoints", rotated["ours"])]
    label = "%s %d" % (both["scene"], both["size"])
    for solver, side in sides:
        q = side["quality"]
        print("| %s | %d | %s | %.4f | %.2e | %.4f | %s |" % (
            label, both["bodies"], solver, q["maxDrift"], q["restingKineticEnergy"], q["maxPenetration"],
            yn(q["stacksStanding"])))
PY
  exit 0
fi

mkdir -p build/bench
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
python3 - build/bench "${names[@]}" <<'PY'
import json, os, sys
folder, names = sys.argv[1], sys.argv[2:]
print("| scene | size | bodies | contact points | joint rows | SI ms/step | ours ms/step | ours / SI | SI p99 / max | ours p99 / max | p99 ours / SI | groups | max penetration SI / ours | max joint error SI / ours | standing SI / ours |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
def num(v):
    return "-" if v is None else "%.3f" % v
def yn(v):
    return "-" if v is None else ("yes" if v else "no")
def ms(v):
    return "%.3f" % v if v < 1 else "%.1f" % v
for name in names:
    d = json.load(open(os.path.join(folder, name + ".json")))
    si, o = d["si"], d["ours"]
    ts, to = si["msPerStep"], o["msPerStep"]
    print("| %s | %d | %d | %d | %d | %s | %s | %.2f | %s / %s | %s / %s | %.2f | %d | %.3f / %.3f | %s / %s | %s / %s |" % (
        d["scene"], d["size"], d["bodies"], d["contactPoints"], o["jointRows"], ms(ts["median"]), ms(to["median"]),
        d["ratioOursOverSi"], ms(ts["p99"]), ms(ts["max"]), ms(to["p99"]), ms(to["max"]), to["p99"] / ts["p99"],
        o["groups"], si["quality"]["maxPenetration"], o["quality"]["maxPenetration"],
        num(si["quality"]["maxJointError"]), num(o["quality"]["maxJointError"]),
        yn(si["quality"]["stacksStanding"]), yn(o["quality"]["stacksStanding"])))
PY
