#!/usr/bin/env bash
# Runs benchmarks and keeps their JSON in docs/bench/MACHINE/KIND/STAMP/ with meta.json (commit,
# date, load), then regenerates the tables of README.md, docs/performance.md and docs/quality.md
# and docs/growth.png from every kept run (scripts/perf_report.py docs). Commit what it wrote:
# the docs' figures are never typed by hand.
#
#   bash scripts/record-bench.sh MACHINE speed [speed ...]   # scripts/benchmarks.sh, once per word
#   bash scripts/record-bench.sh MACHINE busy                # the same beside a busy loop on one core
#   bash scripts/record-bench.sh MACHINE quality growth startup hardware
#   bash scripts/record-bench.sh MACHINE docs                # regenerate only
#
# MACHINE names the machine (a folder); docs/bench/MACHINE/machine.json describes it (written
# on first use from lscpu and the OpenCL device: edit its "description" and "short" by hand).
# The plot needs Debian's python3-matplotlib; without it the tables are still written.
set -euo pipefail
cd "$(dirname "$0")/.."
[[ $# -ge 2 ]] || { sed -n '2,14p' "$0"; exit 2; }
machine="$1"
shift
dir="docs/bench/$machine"
mkdir -p "$dir"
# Debian's python3 has matplotlib where a user-installed one may not.
py=python3
[[ -x /usr/bin/python3 ]] && py=/usr/bin/python3

if [[ ! -f "$dir/machine.json" ]]; then
  cpu="$(lscpu | sed -n 's/^Model name: *//p' | head -1)"
  "$py" - "$dir/machine.json" "$cpu" "$(nproc)" <<'PY'
import json, sys
path, cpu, cores = sys.argv[1], sys.argv[2], int(sys.argv[3])
json.dump({"description": "%d cores, %s, PoCL's CPU device" % (cores, cpu), "short": "%d cores, PoCL" % cores},
          open(path, "w"), indent=2)
PY
fi

keep() {  # keep KIND FROM: copies FROM's JSON and writes meta.json
  local kind="$1" from="$2" stamp to
  stamp="$(date -u +%Y%m%dT%H%M%SZ)"
  to="$dir/$kind/$stamp"
  mkdir -p "$to"
  cp "$from"/*.json "$to/"
  "$py" - "$to/meta.json" "$machine" "$(git rev-parse HEAD)$(git diff --quiet HEAD -- bullet_plugin kernels || echo +changes)" \
    "$(cut -d' ' -f1-3 /proc/loadavg)" <<'PY'
import json, sys, datetime
path, machine, commit, load = sys.argv[1:]
json.dump({"machine": machine, "commit": commit, "date": datetime.datetime.utcnow().strftime("%Y-%m-%d %H:%M UTC"),
           "load": load}, open(path, "w"), indent=2)
PY
  echo "record-bench: kept $to" >&2
}

for kind in "$@"; do
  case "$kind" in
    speed) bash scripts/benchmarks.sh && keep speed build/bench ;;
    busy)  # the speed scenes with another process busy on the last core (a game's neighbour)
      taskset -c "$(($(nproc) - 1))" sh -c 'while :; do :; done' &
      busy=$!
      trap 'kill "$busy" 2>/dev/null || true' EXIT  # the loop ends with this script, however it ends
      bash scripts/benchmarks.sh && keep busy build/bench
      kill "$busy"
      trap - EXIT ;;
    quality) bash scripts/benchmarks.sh --quality && keep quality build/quality ;;
    growth) bash scripts/growth.sh && keep growth build/growth ;;
    startup)
      bash scripts/build.sh >/dev/null
      mkdir -p build/startup
      rm -f build/startup/*.json
      build/demos/startup --cold-warm >build/startup/startup.json
      cache="$(mktemp -d /tmp/btocl-pocl-cache-XXXXXX)"
      POCL_CACHE_DIR="$cache" BT_OPENCL_KERNEL_BINARIES=off build/demos/startup --kernels >build/startup/kernels-cold.json
      POCL_CACHE_DIR="$cache" BT_OPENCL_KERNEL_BINARIES=off build/demos/startup --kernels >build/startup/kernels-warm.json
      rm -rf "$cache"
      cache="$(mktemp -d /tmp/btocl-pocl-cache-XXXXXX)"
      POCL_CACHE_DIR="$cache" build/demos/startup --kernels >build/startup/kernels-binary.json
      rm -rf "$cache"
      keep startup build/startup ;;
    hardware)
      bash scripts/build.sh >/dev/null
      mkdir -p build/hardware
      rm -f build/hardware/*.json
      build/demos/memory_bandwidth >build/hardware/bandwidth.json
      keep hardware build/hardware ;;
    docs) ;;
    *) echo "record-bench: unknown kind '$kind' (speed, busy, quality, growth, startup, hardware, docs)" >&2; exit 2 ;;
  esac
done
"$py" scripts/perf_report.py docs
