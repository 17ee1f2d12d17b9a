#!/usr/bin/env bash
# Sets up, builds and runs the side-by-side benchmark on every scene, then prints the README's
# results table (Markdown) from the JSON summaries. The JSON files stay in build/bench/.
# Each scene first runs a few steps of our solver alone: PoCL compiles kernel variants the first
# time it meets a launch shape and caches them, and that one-time cost is not a step's cost.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh >/dev/null
bench=build/demos/btocl_bench
mkdir -p build/bench
runs=(
  "pyramid 20 300"
  "wall 10 300"
  "pile 1000 300"
  "columns 12000 300"
  "block 12000 30"
)
for run in "${runs[@]}"; do
  read -r scene size steps <<<"$run"
  echo "== $scene (size $size, $steps steps)" >&2
  "$bench" --scene "$scene" --size "$size" --steps 8 --solver ocl >/dev/null 2>&1 || true
  "$bench" --scene "$scene" --size "$size" --steps "$steps" --iterations 10 --json "build/bench/$scene.json" >/dev/null
done
python3 - build/bench <<'PY'
import json, os, sys
folder = sys.argv[1]
order = ["pyramid", "wall", "pile", "columns", "block"]
print("| scene | bodies | contact points | SI ms/step | ours ms/step | ours / SI | groups | batches max / mean | max penetration SI / ours | standing SI / ours |")
print("|---|---|---|---|---|---|---|---|---|---|")
def yn(v):
    return "-" if v is None else ("yes" if v else "no")
for name in order:
    path = os.path.join(folder, name + ".json")
    if not os.path.exists(path):
        continue
    d = json.load(open(path))
    si, o = d["si"], d["ours"]
    print("| %s | %d | %d | %.1f | %.1f | %.2f | %d | %d / %.1f | %.3f / %.3f | %s / %s |" % (
        name, d["bodies"], d["contactPoints"], si["msPerStep"]["median"], o["msPerStep"]["median"],
        d["ratioOursOverSi"], o["groups"], o["batchesMax"], o["batchesMean"],
        si["quality"]["maxPenetration"], o["quality"]["maxPenetration"],
        yn(si["quality"]["stacksStanding"]), yn(o["quality"]["stacksStanding"])))
PY
