#!/usr/bin/env python3
"""Tables (and the growth plot) from btocl_bench and startup JSON: the one place that prints them.

  perf_report.py speed DIR                 Markdown table of one speed run (scripts/benchmarks.sh)
  perf_report.py quality DIR NAME...       resting-quality table (scripts/benchmarks.sh --quality)
  perf_report.py growth DIR NAME...        growth table (scripts/growth.sh)
  perf_report.py docs                      rewrites the generated blocks of README.md,
                                           docs/performance.md and docs/quality.md, and
                                           docs/growth.png, from the runs kept in docs/bench/

docs/bench/MACHINE/KIND/STAMP/ holds what scripts/record-bench.sh copied from one run (KIND:
speed, quality, growth, startup) with meta.json (commit, date, load). A generated block lies
between "<!-- generated: NAME -->" and "<!-- end generated -->"; the text around it is written
by hand and kept.
"""
import glob
import json
import os
import re
import statistics
import sys

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
BENCH = os.path.join(ROOT, "docs", "bench")

# The speed runs' scenes in the order a reader meets them: a new user's first scenes, then larger.
SPEED_ORDER = ["basic-5", "chain-20", "pyramid-10", "machine-64", "pyramid-20", "wall-10", "pile-1000",
               "ragdolls-200", "pyramid3d-20", "columns-12000", "block-12000"]
SCENE_WORDS = {
    "basic": "Bullet's BasicDemo, 5x5x5 boxes",
    "chain": "hinge chain, 20 links",
    "pyramid": "2D pyramid, base %d",
    "machine": "chains and pendulums, paddles",
    "wall": "brick wall, %d courses",
    "pile": "%d boxes dropped",
    "ragdolls": "%d ragdolls",
    "pyramid3d": "3D pyramid, base %d",
    "columns": "the paper's columns, %d boxes",
    "block": "dense block, %d boxes",
}


def load(path):
    with open(path) as f:
        return json.load(f)


def ms(v):
    return "%.3f" % v if v < 1 else "%.1f" % v


def yn(v):
    return "-" if v is None else ("yes" if v else "no")


def num(v):
    return "-" if v is None else "%.3f" % v


def path_of(ours):
    """How our solver ran the scene's steps: on the host, whole on the device, split on the
    device, or split on the host (splitStepsOnHost)."""
    on_host = ours.get("stepsOnHost", 0)
    split_on_host = ours.get("stepsOnHostSplit", 0)
    whole = ours.get("stepsWholeOnDevice", 0)
    kinds = []
    if on_host - split_on_host > 0:
        kinds.append("host")
    if whole:
        kinds.append("whole")
    if ours.get("stepsDone", 0) - on_host - whole > 0 and ours.get("groups"):
        kinds.append("split")
    if split_on_host:
        kinds.append("split on host")
    return "+".join(kinds) or "-"


def describe(d):
    words = SCENE_WORDS.get(d["scene"], d["scene"] + " %d")
    return words % d["size"] if "%d" in words else words


# --- one run, printed by the scripts that ran it ---------------------------------------------------

def print_speed(folder):
    names = [n for n in SPEED_ORDER if os.path.exists(os.path.join(folder, n + ".json"))]
    names += sorted(os.path.basename(p)[:-5] for p in glob.glob(os.path.join(folder, "*.json"))
                    if os.path.basename(p)[:-5] not in names and not p.endswith("meta.json"))
    print("| scene | size | bodies | contact points | joint rows | path | SI ms/step | ours ms/step | ours / SI "
          "| SI p99 / max | ours p99 / max | p99 ours / SI | max penetration SI / ours | max joint error SI / ours "
          "| standing SI / ours |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for name in names:
        d = load(os.path.join(folder, name + ".json"))
        si, o = d["si"], d["ours"]
        ts, to = si["msPerStep"], o["msPerStep"]
        print("| %s | %d | %d | %d | %d | %s | %s | %s | %.2f | %s / %s | %s / %s | %.2f | %.3f / %.3f | %s / %s "
              "| %s / %s |" % (
                  d["scene"], d["size"], d["bodies"], d["contactPoints"], o["jointRows"], path_of(o),
                  ms(ts["median"]), ms(to["median"]), d["ratioOursOverSi"], ms(ts["p99"]), ms(ts["max"]),
                  ms(to["p99"]), ms(to["max"]), to["p99"] / ts["p99"],
                  si["quality"]["maxPenetration"], o["quality"]["maxPenetration"],
                  num(si["quality"]["maxJointError"]), num(o["quality"]["maxJointError"]),
                  yn(si["quality"]["stacksStanding"]), yn(o["quality"]["stacksStanding"])))


def quality_rows(folder, names):
    for name in names:
        both = load(os.path.join(folder, name + ".json"))
        randomized = load(os.path.join(folder, name + "-randomized.json"))
        rotated = load(os.path.join(folder, name + "-rotated.json"))
        sides = [("SI", both["si"]), ("SI randomized", both["siRandomized"]), ("ours", both["ours"]),
                 ("ours randomized", randomized["ours"]), ("ours, rotatePoints", rotated["ours"])]
        for solver, side in sides:
            yield both, solver, side["quality"]


def quality_lines(folder, names):
    lines = ["| scene | bodies | solver | max drift (m) | resting kinetic energy (J) | max penetration (m) | standing |",
             "|---|---|---|---|---|---|---|"]
    for both, solver, q in quality_rows(folder, names):
        lines.append("| %s %d | %d | %s | %.4f | %.2e | %.4f | %s |" % (
            both["scene"], both["size"], both["bodies"], solver, q["maxDrift"], q["restingKineticEnergy"],
            q["maxPenetration"], yn(q["stacksStanding"])))
    return lines


def growth_round_paths(folder, name, solver):
    """One solver's JSON of each round (scripts/growth.sh): NAME-SOLVER.json, then NAME-SOLVER.R.json."""
    later = glob.glob(os.path.join(folder, "%s-%s.*.json" % (name, solver)))
    rounds = sorted((int(p.rsplit(".", 2)[1]), p) for p in later if p.rsplit(".", 2)[1].isdigit())
    return [(1, os.path.join(folder, "%s-%s.json" % (name, solver)))] + rounds


def median_round_path(folder, name_solver):
    """Of a growth run's rounds of NAME-SOLVER, the one whose median step is the rounds' median
    (the lower middle of an even count)."""
    name, solver = name_solver.rsplit("-", 1)
    found = [(load(p)["ours" if solver == "ocl" else "si"]["msPerStep"]["median"], p)
             for _, p in growth_round_paths(folder, name, solver) if os.path.exists(p)]
    if not found:
        return os.path.join(folder, name_solver + ".json")
    found.sort()
    return found[(len(found) - 1) // 2][1]


def growth_rows(folder, names):
    """Per size, the rounds' runs: each side's median ms per step over the rounds, the median of
    the rounds' ratios (a round's two runs lie minutes apart, the rounds further) and their range."""
    for name in names:
        si_runs = dict(growth_round_paths(folder, name, "si"))
        oc_runs = dict(growth_round_paths(folder, name, "ocl"))
        pairs = [(load(si_runs[r]), load(oc_runs[r])) for r in sorted(si_runs) if r in oc_runs]
        first_si, first_oc = pairs[0]
        si_ms = [si["si"]["msPerStep"]["median"] for si, _ in pairs]
        oc_ms = [oc["ours"]["msPerStep"]["median"] for _, oc in pairs]
        ratios = [o / s for s, o in zip(si_ms, oc_ms)]
        yield {
            "scene": first_si["scene"], "bodies": first_si["bodies"], "steps": first_si["steps"], "rounds": len(pairs),
            "siPoints": first_si["si"]["contactPointsMax"], "oursPoints": first_oc["ours"]["contactPointsMax"],
            "siMs": statistics.median(si_ms), "oursMs": statistics.median(oc_ms),
            "ratio": statistics.median(ratios), "ratioLow": min(ratios), "ratioHigh": max(ratios),
            "siPer1K": statistics.median(si["si"]["msPer1000ContactPoints"] for si, _ in pairs),
            "oursPer1K": statistics.median(oc["ours"]["msPer1000ContactPoints"] for _, oc in pairs),
            "siRss": max(si["peakRssBytes"] for si, _ in pairs), "oursRss": max(oc["peakRssBytes"] for _, oc in pairs),
            "deviceBytes": first_oc["ours"]["deviceBytes"],
            "deviceBytesPerPoint": first_oc["ours"]["deviceBytesPerContactPoint"],
        }


def growth_lines(folder, names):
    lines = ["| scene | boxes | steps | rounds | contact points (most) SI / ours | SI ms/step | ours ms/step "
             "| ours / SI (rounds' range) | SI ms per 1K points | ours ms per 1K points | SI peak RSS MB "
             "| ours peak RSS MB | ours device MB | ours device bytes per point |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    mb = lambda b: b / 2**20
    for g in growth_rows(folder, names):
        spread_text = " (%.2f-%.2f)" % (g["ratioLow"], g["ratioHigh"]) if g["rounds"] > 1 else ""
        lines.append("| %s | %d | %d | %d | %d / %d | %.1f | %.1f | %.2f%s | %.3f | %.3f | %.0f | %.0f | %.0f | %.0f |" % (
            g["scene"], g["bodies"], g["steps"], g["rounds"], g["siPoints"], g["oursPoints"], g["siMs"], g["oursMs"],
            g["ratio"], spread_text, g["siPer1K"], g["oursPer1K"], mb(g["siRss"]), mb(g["oursRss"]),
            mb(g["deviceBytes"]), g["deviceBytesPerPoint"]))
    return lines


# --- the kept runs, for the docs ------------------------------------------------------------------

def runs(machine, kind):
    """The kept runs of one kind, oldest first: (folder, meta)."""
    out = []
    for folder in sorted(glob.glob(os.path.join(BENCH, machine, kind, "*"))):
        meta_path = os.path.join(folder, "meta.json")
        out.append((folder, load(meta_path) if os.path.exists(meta_path) else {}))
    return out


def spread(values, fmt="%.2f"):
    return ", ".join(fmt % v for v in values)


def speed_table(machine, run_list):
    """Every scene of the runs: medians' ratio and p99's ratio, each run apart."""
    per_scene = {}
    for folder, _ in run_list:
        for path in glob.glob(os.path.join(folder, "*.json")):
            if path.endswith("meta.json"):
                continue
            d = load(path)
            per_scene.setdefault("%s-%d" % (d["scene"], d["size"]), []).append(d)
    names = [n for n in SPEED_ORDER if n in per_scene] + sorted(n for n in per_scene if n not in SPEED_ORDER)
    lines = ["| scene | bodies | contact points | joint rows | ours ran it | SI ms/step | ours ms/step "
             "| ours / SI, median | ours / SI, p99 | ours / SI, worst step | max penetration SI / ours "
             "| max joint error SI / ours |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for name in names:
        ds = per_scene[name]
        last = ds[-1]
        si_med = statistics.median(d["si"]["msPerStep"]["median"] for d in ds)
        ours_med = statistics.median(d["ours"]["msPerStep"]["median"] for d in ds)
        lines.append("| %s | %d | %d | %d | %s | %s | %s | %s | %s | %s | %.3f / %.3f | %s / %s |" % (
            describe(last), last["bodies"], last["contactPoints"], last["ours"]["jointRows"], path_of(last["ours"]),
            ms(si_med), ms(ours_med),
            spread(d["ratioOursOverSi"] for d in ds),
            spread(d["ours"]["msPerStep"]["p99"] / d["si"]["msPerStep"]["p99"] for d in ds),
            spread(d["ours"]["msPerStep"]["max"] / d["si"]["msPerStep"]["max"] for d in ds),
            last["si"]["quality"]["maxPenetration"], last["ours"]["quality"]["maxPenetration"],
            num(last["si"]["quality"]["maxJointError"]), num(last["ours"]["quality"]["maxJointError"])))
    return lines, per_scene, names


def glance_table(per_scene, names):
    """The README's short table: where the swap wins and where it loses, by the runs' medians."""
    lines = ["| scene | ours / SI, median | ours / SI, p99 | |", "|---|---|---|---|"]
    for name in names:
        ds = per_scene[name]
        ratios = [d["ratioOursOverSi"] for d in ds]
        p99 = [d["ours"]["msPerStep"]["p99"] / d["si"]["msPerStep"]["p99"] for d in ds]
        verdict = "faster" if max(ratios) < 0.95 else ("slower" if min(ratios) > 1.05 else "about the same")
        rng = lambda v: "%.2f" % v[0] if "%.2f" % min(v) == "%.2f" % max(v) else "%.2f to %.2f" % (min(v), max(v))
        lines.append("| %s | %s | %s | %s |" % (describe(ds[-1]), rng(ratios), rng(p99), verdict))
    return lines


def run_sources(run_list):
    return "; ".join("%s at %s (load %s)" % (m.get("date", "?"), m.get("commit", "?")[:7], m.get("load", "?"))
                     for _, m in run_list)


def quality_names(folder):
    return sorted({os.path.basename(p)[:-5] for p in glob.glob(os.path.join(folder, "*.json"))
                   if not re.search(r"-(randomized|rotated)\.json$|meta\.json$", p)})


def growth_names(folder):
    return sorted({os.path.basename(p)[:-len("-si.json")] for p in glob.glob(os.path.join(folder, "*-si.json"))},
                  key=lambda n: (n.split("-")[0], int(n.split("-")[1])))


def growth_plot(run_list, out_png):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("perf_report: no matplotlib (Debian: python3-matplotlib); %s left as it is" % out_png, file=sys.stderr)
        return False
    folder, meta = run_list[-1]
    series = {}
    for g in growth_rows(folder, growth_names(folder)):
        for label, points, ms_step in (("Bullet's solver (SI)", g["siPoints"], g["siMs"]),
                                       ("btOpenCLConstraintSolver", g["oursPoints"], g["oursMs"])):
            series.setdefault((g["scene"], label), []).append((points, ms_step))
    fig, ax = plt.subplots(figsize=(7, 4.5), dpi=100)
    styles = {"Bullet's solver (SI)": dict(color="#b03030"), "btOpenCLConstraintSolver": dict(color="#2060b0")}
    marks = {"block": "o-", "columns": "s--"}
    for (scene, label), pts in sorted(series.items()):
        pts.sort()
        ax.plot([p[0] for p in pts], [p[1] for p in pts], marks.get(scene, "^-"), label="%s: %s" % (scene, label),
                **styles[label])
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("contact points in the step (most over the run)")
    ax.set_ylabel("solver ms per step (median)")
    ax.set_title("How the solver's cost grows (each solver in its own process)", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.text(0.01, 0.01, "%s, commit %s" % (meta.get("machine", ""), meta.get("commit", "?")[:7]), fontsize=7,
             color="#666666")
    fig.tight_layout()
    fig.savefig(out_png)
    return True


def startup_table(run_list):
    """Which start-up cost is paid how often: the parts (startup --kernels: an empty cache with the
    build's binaries, an empty cache compiling, a warm cache), then the solver made and a scene's
    first second as a user meets them (startup --cold-warm), in the same three columns."""
    def each(values, fmt):
        return ", ".join(fmt % v for v in values) or "-"
    def parts_of(name):
        return [load(os.path.join(f, name)) for f, _ in run_list if os.path.exists(os.path.join(f, name))]
    binary, cold, warm = parts_of("kernels-binary.json"), parts_of("kernels-cold.json"), parts_of("kernels-warm.json")
    users = [load(os.path.join(f, "startup.json")) for f, _ in run_list]
    lines = ["| what | how often | empty cache, the build's binaries | empty cache, compiled | warm cache |",
             "|---|---|---|---|---|"]
    if cold:
        programs = lambda d: sum(p["ms"] for p in d["programs"])
        kernels = lambda d: sum(k["ms"] for k in d["kernels"]) + d.get("sort_and_scan_warm_up_ms", 0)
        count = len(cold[-1]["kernels"])
        lines.append("| the program built (from its binary, or compiled) | compiled: once per machine and PoCL version; "
                     "else once per solver | %s | %s | %s |" % (
            each([programs(d) for d in binary], "%.0f ms"), each([programs(d) for d in cold], "%.0f ms"),
            each([programs(d) for d in warm], "%.0f ms")))
        lines.append("| the code of the step's %d kernels and of the sort and scan generated (warm-up launches) "
                     "| compiled: once per machine; else once per process | %s | %s | %s |" % (
            count, each([kernels(d) for d in binary], "%.0f ms"), each([kernels(d) for d in cold], "%.0f ms"),
            each([kernels(d) for d in warm], "%.0f ms")))
    # startup --cold-warm prints one {"cold": ..., "warm": ..., "cold_compiled": ...} per scene.
    by_scene = {}
    for u in users:
        for run in u:
            by_scene.setdefault(run["cold"]["scene"], []).append(run)
    rows = [("the solver made (first in the process)", "once per solver", "construct_ms", 1, "%.0f ms"),
            ("made + the first second of steps", "", "construct_plus_first_second_ms", 1000, "%.2f s"),
            ("the first step with contacts", "", "first_contact_step_ms", 1, "%.1f ms"),
            ("slowest step / median step", "", "slowest_over_median", 1, "%.1fx")]
    for scene, rs in by_scene.items():
        for label, often, key, scale, fmt in rows:
            lines.append("| %s: %s | %s | %s | %s | %s |" % (
                scene, label, often, *(each([r[side][key] / scale for r in rs if side in r], fmt)
                                       for side in ("cold", "cold_compiled", "warm"))))
    return lines


# A lane block's row: BTOCL_LANE_ROW_FLOATS floats, read from kernels/btocl_shared.h.
def lane_row_floats():
    header = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "kernels", "btocl_shared.h")
    with open(header) as f:
        return int(re.search(r"#define BTOCL_LANE_ROW_FLOATS (\d+)", f.read()).group(1))


LANE_ROW_FLOATS = lane_row_floats()


def limit_table(speed_runs, hardware_runs, growth_runs=(), scenes=("block-12000", "pyramid3d-20"),
                growth_scenes=("block-48000-ocl",)):
    """How far the split scenes' solve phase is from what the cores can do: row updates per second
    per core, the bytes a row update moves, and the rows' stream against the measured bandwidth.
    Scenes at rest only: their last step's counts stand for every step's, whose median solve
    time is read. In lanes (simdLanes > 1) a row lies in a block of W rows, empty places too:
    a row update moves its lane row and impulse over the layout's row fill. The growth run's
    largest block (ours alone in its process) shows the rows far past the last-level cache."""
    hw = load(os.path.join(hardware_runs[-1][0], "bandwidth.json"))
    size = hw["bytes"]
    cores = hw["cores"]
    l3_mib = hw.get("cacheKiB", {}).get("L3", 0) / 1024
    all_cores = [t for t in hw["threadsPerCore"] if t["threads"] == cores][-1]
    one_core = [t for t in hw["threadsPerCore"] if t["threads"] == 1][-1]
    lines = ["Bandwidth (`memory_bandwidth`, arrays of %d MiB, best of its runs): one thread reads %.1f GB/s and "
             "copies %.1f; %d threads read %.1f and copy %.1f. Last-level cache: %.0f MiB." % (
                 hw["arrayMiB"], one_core["readGBps"], one_core["copyGBps"], cores, all_cores["readGBps"],
                 all_cores["copyGBps"], l3_mib), "",
             "| scene | rows | row updates a step | solve ms | lanes (row fill) | ns per row update on a core "
             "| row updates per s per core | bytes a row update moves | rows' MiB (records and impulses) "
             "| bodies' and constraints' MiB | rows' stream GB/s | of the %d cores' read bandwidth |" % cores,
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    paths = [os.path.join(speed_runs[-1][0], name + ".json") for name in scenes]
    if growth_runs:
        paths += [median_round_path(growth_runs[-1][0], name) for name in growth_scenes]
    for path in paths:
        if not os.path.exists(path):
            continue
        d = load(path)
        o = d["ours"]
        # Every manifold of a resting scene has points: one constraint each.
        rows, points, constraints = o["constraintRows"], o["contactPoints"], o["manifolds"]
        updates = d["iterations"] * rows + points  # every velocity iteration, and the warm start
        solve_ms = o["phasesMsMedian"]["solve"]
        ns_core = solve_ms * 1e6 * cores / updates
        lanes = o.get("simdLanes") or 1
        fill = o.get("laneRowFill") or 0
        # A row update reads the row's record and reads and writes its impulse; where the rows
        # outgrow the last-level cache, every pass streams them from memory. The bodies' records
        # and deltas and the constraints' records, read once a constraint in each pass, are
        # smaller and stay in the caches on these scenes.
        if lanes > 1 and fill > 0:
            record = LANE_ROW_FLOATS * 4 / fill
            impulse = size["appliedImpulse"] / fill
            lanes_text = "%d (%.2f)" % (lanes, fill)
        else:
            record, impulse, lanes_text = size["solveRow"], size["appliedImpulse"], "1"
        row_bytes = record + 2 * impulse
        rows_mib = rows * (record + impulse) / 2**20
        others_mib = (d["bodies"] * (size["body"] + size["bodyDelta"]) + constraints * size["constraint"]) / 2**20
        gbps = updates * row_bytes / (solve_ms * 1e-3) / 1e9
        lines.append("| %s | %d | %.2fM | %.1f | %s | %.1f | %.0fM | %.0f | %.0f | %.1f | %.1f | %.0f%% |" % (
            describe(d), rows, updates / 1e6, solve_ms, lanes_text, ns_core, 1e3 / ns_core, row_bytes, rows_mib,
            others_mib, gbps, 100.0 * gbps / all_cores["readGBps"]))
    return lines


def replace_block(path, name, lines):
    with open(path) as f:
        text = f.read()
    pattern = re.compile(r"(<!-- generated: %s -->\n).*?(<!-- end generated -->)" % re.escape(name), re.S)
    if not pattern.search(text):
        sys.exit("perf_report: %s has no block '%s'" % (path, name))
    text = pattern.sub(lambda m: m.group(1) + "\n".join(lines) + "\n" + m.group(2), text)
    with open(path, "w") as f:
        f.write(text)


def newest(run_list):
    return max((m.get("date", "") for _, m in run_list), default="")


def docs():
    machines = sorted(os.path.basename(p) for p in glob.glob(os.path.join(BENCH, "*")) if os.path.isdir(p))
    if not machines:
        sys.exit("perf_report: nothing kept in docs/bench/ (scripts/record-bench.sh)")
    # The machine recorded last first: each machine's speed and busy tables stand one after
    # another; the other kinds come from the first machine that has them.
    machines.sort(key=lambda m: newest(runs(m, "speed")), reverse=True)
    perf = os.path.join(ROOT, "docs", "performance.md")
    readme = os.path.join(ROOT, "README.md")
    info = {m: load(os.path.join(BENCH, m, "machine.json")) for m in machines}
    speed_lines, glance_lines, busy_lines = [], [], []
    for machine in machines:
        speed = runs(machine, "speed")
        if speed:
            lines, per_scene, names = speed_table(machine, speed)
            speed_lines += (["", ""] if speed_lines else []) + [
                "Machine `%s`: %s." % (machine, info[machine].get("description", "")), "",
                "Runs: %s." % run_sources(speed), ""] + lines
            glance_lines += ([""] if glance_lines else []) + glance_table(per_scene, names) + [
                "", "(%d runs on %s, `docs/bench/%s/`)" % (len(speed), info[machine].get("short", machine), machine)]
        busy = runs(machine, "busy")
        if busy:
            busy_lines += (["", ""] if busy_lines else []) + [
                "Machine `%s`. Runs: %s." % (machine, run_sources(busy)), ""] + speed_table(machine, busy)[0]
    if speed_lines:
        replace_block(perf, "speed", speed_lines)
        replace_block(readme, "glance", glance_lines)
    if busy_lines:
        replace_block(perf, "busy", busy_lines)

    def first(kind):
        return next(((m, runs(m, kind)) for m in machines if runs(m, kind)), (None, []))

    machine, growth = first("growth")
    if growth:
        folder = growth[-1][0]
        replace_block(perf, "growth", ["Run: %s, machine `%s`." % (run_sources(growth[-1:]), machine), ""] +
                      growth_lines(folder, growth_names(folder)))
        growth_plot(growth, os.path.join(ROOT, "docs", "growth.png"))
    machine, startup = first("startup")
    if startup:
        replace_block(perf, "startup", ["Runs: %s, machine `%s`." % (run_sources(startup), machine), ""] +
                      startup_table(startup))
        replace_block(readme, "startup", startup_table(startup) + [
            "", "(%s, `docs/bench/%s/`)" % (info[machine].get("short", machine), machine)])
    machine, hardware = first("hardware")
    speed = runs(machine, "speed") if machine else []
    growth = runs(machine, "growth") if machine else []
    if hardware and speed:
        replace_block(perf, "limit", ["Runs: %s; %s; growth %s, machine `%s`." % (
            run_sources(speed[-1:]), run_sources(hardware[-1:]), run_sources(growth[-1:]), machine), ""] +
            limit_table(speed, hardware, growth))
    machine, quality = first("quality")
    if quality:
        replace_block(os.path.join(ROOT, "docs", "quality.md"), "quality",
                      ["Run: %s, machine `%s`." % (run_sources(quality[-1:]), machine), ""] +
                      quality_lines(quality[-1][0], quality_names(quality[-1][0])))


def main(argv):
    if len(argv) >= 2 and argv[0] == "speed":
        print_speed(argv[1])
    elif len(argv) >= 2 and argv[0] == "quality":
        print("\n".join(quality_lines(argv[1], argv[2:])))
    elif len(argv) >= 2 and argv[0] == "growth":
        print("\n".join(growth_lines(argv[1], argv[2:])))
    elif argv == ["docs"]:
        docs()
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main(sys.argv[1:])
