#!/usr/bin/env bash
# Speed and memory benchmark; not a test. Two parts:
#
#   bash scripts/bench-speed.sh pairs [K=2] [RUNS=3]
#     A fixed set of frame pairs, K from every list of ../shared/lists (evenly spread over the
#     list), each registered RUNS times as its own process after one warm-up, alternating
#     `zeroreg register` (default pipeline) with `zeroreg register --baseline sift` (OpenCV SIFT +
#     ratio test + RANSAC) of the same pair, so that both see the same machine load. Prints the
#     median of every stage of timings_ms (read_scans and load_models included), the median
#     whole-process wall time and peak RSS per list for both, and the ratio zeroreg / SIFT.
#
#   bash scripts/bench-speed.sh eval [LIMIT=20] [LIST ...]   (list names; default: every non-cross list)
#     `zeroreg eval pairs --limit LIMIT` over each sequence list as a user runs it (default
#     --jobs: one per processor), then with --jobs 1, with --jobs 1 and without the
#     prepared-scan cache (--prepared-cache 0: every pair prepares both scans, as registering them
#     one by one in one process does), and the same LIMIT pairs registered one by one as their own
#     processes (`zeroreg register` per pair, as a shell loop would): total wall time, CPU time
#     and peak RSS of each, and the ratios of each eval to the processes.
#
#   bash scripts/bench-speed.sh fragments [K=6] [RUNS=3]
#     K fragment pairs of 3DMatch / 3DLoMatch redkitchen (evenly spread over the two gt.log files
#     of ../shared/data/3dmatch-gt, half from each), each registered RUNS times as its own process
#     (`zeroreg register -s FRAGMENT -t FRAGMENT --timings`) after one warm-up: median of every
#     stage, of the in-process total and of the whole process, and the peak RSS. The fragments
#     come from the cache `zeroreg eval 3dmatch` fills (FRAGMENTS, default
#     cache/fragments/7-scenes-redkitchen; `zeroreg eval 3dmatch ... --fuse-only` fills it).
#
# Extra options after the positional ones go to every zeroreg (e.g. --set threads=1).
# Environment: ZEROREG_BIN (default build/zeroreg), LISTS_DIR (../shared/lists), DATA
# (../shared/data). Timings on a shared machine are noisy: compare medians of a run, not runs.
set -euo pipefail
repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo_root"
mode="${1:-pairs}"
shift || true
exec /usr/bin/python3 - "$mode" "$@" <<'PY'
import json, os, statistics, subprocess, sys, tempfile, time

mode, args = sys.argv[1], sys.argv[2:]
binary = os.environ.get("ZEROREG_BIN", "build/zeroreg")
lists_dir = os.environ.get("LISTS_DIR", "../shared/lists")
data_dir = os.environ.get("DATA", "../shared/data")
SCENES = {"redkitchen": "7scenes-redkitchen", "hololens": "hololens-office",
          "cabinet": "tum-fr3-cabinet"}


def positional(n, defaults):
    out = []
    for k in range(n):
        if args and not args[0].startswith("-"):
            out.append(args.pop(0))
        else:
            out.append(defaults[k])
    return out


def timed(command, cpu=None):
    """Runs command; returns (exit code, wall seconds, peak RSS MiB) of that process alone, and
    appends its CPU seconds (user + system) to `cpu` when given: on a loaded machine the CPU time
    is the steadier measure of work done."""
    with tempfile.NamedTemporaryFile("r", suffix=".rss") as rss:
        start = time.perf_counter()
        code = subprocess.call(["/usr/bin/time", "-f", "%M %U %S", "-o", rss.name] + command,
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        wall = time.perf_counter() - start
        fields = rss.read().split()
        if cpu is not None:
            cpu.append(float(fields[-2]) + float(fields[-1]))
        return code, wall, int(fields[-3]) / 1024


def list_pairs(name, k):
    rows = [l.split() for l in open(f"{lists_dir}/{name}/pairs.txt")
            if l.strip() and not l.startswith("#")]
    picks = sorted({round(i * (len(rows) - 1) / max(1, k - 1)) for i in range(k)})
    return [(int(rows[p][0]), int(rows[p][1])) for p in picks]


def scene(name):
    return f"{data_dir}/{SCENES[name.split('-')[0]]}"


def median(values):
    return statistics.median(values) if values else float("nan")


lists = sorted(d for d in os.listdir(lists_dir) if os.path.isfile(f"{lists_dir}/{d}/pairs.txt"))

if mode == "pairs":
    k, runs = (int(x) for x in positional(2, ["2", "3"]))
    out = tempfile.mkdtemp()
    pairs = [(name, i, j) for name in lists for i, j in list_pairs(name, k)]
    stages, per_list, cpu_z, cpu_s = {}, {}, [], []
    first = pairs[0]
    for cmd in ([binary, "register", "-s", f"{scene(first[0])}@{first[2]}", "-t",
                 f"{scene(first[0])}@{first[1]}"] + args,
                [binary, "register", "--baseline", "sift", "-s", f"{scene(first[0])}@{first[2]}",
                 "-t", f"{scene(first[0])}@{first[1]}"] + args):
        timed(cmd)  # warm-up: page cache, models
    for run in range(runs):
        for name, i, j in pairs:
            src, tgt = f"{scene(name)}@{j}", f"{scene(name)}@{i}"
            result = f"{out}/r.json"
            _, wall, rss = timed([binary, "register", "-s", src, "-t", tgt, "--out", result] + args,
                                 cpu_z)
            r = json.load(open(result))["result"]
            for stage, ms in r["timings_ms"].items():
                stages.setdefault(stage, []).append(ms)
            stats = per_list.setdefault(name, {"zeroreg": [], "sift": [], "rss": [], "rss_sift": []})
            stats["zeroreg"].append(wall)
            stats["rss"].append(rss)
            _, wall, rss = timed([binary, "register", "--baseline", "sift", "-s", src, "-t", tgt]
                                 + args, cpu_s)
            stats["sift"].append(wall)
            stats["rss_sift"].append(rss)
    print(f"{len(pairs)} pairs ({k} per list) x {runs} runs, options: {' '.join(args) or '(none)'}")
    print("median wall time per stage of `zeroreg register` (ms, timings_ms):")
    order = ["read_scans", "load_models", "features", "detect", "segment", "objects", "geometry",
             "object_match", "point_match", "match", "estimate", "verify", "refine", "total"]
    for stage in sorted(stages, key=lambda s: order.index(s) if s in order else len(order)):
        values = stages[stage]
        print(f"  {stage:14s} {median(values):8.1f}   (min {min(values):.1f}, max {max(values):.1f})")
    print("\nwhole process, median wall (s) and max peak RSS (MiB):")
    print(f"  {'list':18s} {'zeroreg':>8s} {'sift':>8s} {'ratio':>6s} {'RSS':>6s} {'RSS sift':>8s}")
    all_z, all_s, all_rss = [], [], []
    for name in lists:
        s = per_list[name]
        all_z += s["zeroreg"]
        all_s += s["sift"]
        all_rss += s["rss"]
        print(f"  {name:18s} {median(s['zeroreg']):8.3f} {median(s['sift']):8.3f} "
              f"{median(s['zeroreg']) / median(s['sift']):6.2f} {max(s['rss']):6.0f} "
              f"{max(s['rss_sift']):8.0f}")
    print(f"  {'all':18s} {median(all_z):8.3f} {median(all_s):8.3f} "
          f"{median(all_z) / median(all_s):6.2f} {max(all_rss):6.0f}")
    print(f"CPU seconds (user + system) per process, median: zeroreg {median(cpu_z):.3f}, "
          f"sift {median(cpu_s):.3f}, ratio {median(cpu_z) / median(cpu_s):.2f}; "
          f"load average now {os.getloadavg()[0]:.1f}")
elif mode == "eval":
    (limit,) = positional(1, ["20"])
    chosen = [a for a in args if not a.startswith("-") and a in lists]
    args = [a for a in args if a not in chosen]
    chosen = chosen or [l for l in lists if "cross" not in l]
    print(f"zeroreg eval pairs --limit {limit} {' '.join(args)}: total wall s (CPU s); "
          "ratio = that eval / one process per pair")
    runs = (("default", []), ("--jobs 1", ["--jobs", "1"]),
            ("--jobs 1 uncached", ["--jobs", "1", "--prepared-cache", "0"]))
    print(f"  {'list':18s} " + " ".join(f"{label:>20s}" for label, _ in runs) +
          f" {'processes':>13s} {'RSS MiB':>8s}")
    for name in chosen:
        row = []
        for _, options in runs:
            with tempfile.TemporaryDirectory() as out:
                cpu = []
                code, wall, rss = timed([binary, "eval", "pairs", "--list", f"{lists_dir}/{name}",
                                         "--data", scene(name), "--out", f"{out}/run", "--limit",
                                         limit, "--no-progress"] + options + args, cpu)
                if code != 0:  # 1: some pairs failed with an error; 2: bad input; 3: internal
                    print(f"  {name}: eval failed with exit code {code}", file=sys.stderr)
                row.append((wall, rss, cpu[0]))
        # The same first LIMIT pairs (eval's --limit takes the list's first rows), one process each.
        rows = [l.split() for l in open(f"{lists_dir}/{name}/pairs.txt")
                if l.strip() and not l.startswith("#")][:int(limit)]
        cpu, wall_sum = [], 0.0
        for i, j in ((int(r[0]), int(r[1])) for r in rows):
            code, wall, _ = timed([binary, "register", "-s", f"{scene(name)}@{j}", "-t",
                                   f"{scene(name)}@{i}"] + args, cpu)
            if code not in (0, 1):  # 1 = ran, but the registration is not valid
                print(f"  {name} {i} {j}: register failed with exit code {code}", file=sys.stderr)
            wall_sum += wall
        processes = (wall_sum, 0, sum(cpu))
        cell = lambda r: f"{r[0]:5.2f} ({r[2]:4.1f}) {r[0] / processes[0]:4.2f}"
        print(f"  {name:18s} " + " ".join(f"{cell(r):>20s}" for r in row) +
              f" {processes[0]:6.2f} ({processes[2]:4.1f}) {row[0][1]:8.0f}")
    print(f"load average now {os.getloadavg()[0]:.1f}")
elif mode == "fragments":
    k, runs = (int(x) for x in positional(2, ["6", "3"]))
    fragments = os.environ.get("FRAGMENTS", "cache/fragments/7-scenes-redkitchen")
    gt_root = f"{data_dir}/3dmatch-gt"
    chosen = []
    for bench, count in (("3DMatch", (k + 1) // 2), ("3DLoMatch", k // 2)):
        log = f"{gt_root}/{bench}/7-scenes-redkitchen/gt.log"
        if not os.path.isfile(log):
            sys.exit(f"bench-speed.sh: {log} not found; expected the 3DMatch ground truth")
        rows = [l.split() for l in open(log)]
        # Only pairs whose two fragments are fused (the suite fuses those of its pairs).
        heads = [(int(r[0]), int(r[1])) for r in rows if len(r) == 3 and all(
            os.path.isfile(f"{fragments}/fragment-{f}/scan.json") for f in (r[0], r[1]))]
        if not heads:
            sys.exit(f"bench-speed.sh: no {bench} pair has both fragments in {fragments}; fill "
                     "the cache with `build/zeroreg eval 3dmatch --data ../shared/data/"
                     "7scenes-redkitchen --gt ../shared/data/3dmatch-gt --out results/fuse "
                     "--fuse-only`")
        for p in sorted({round(i * (len(heads) - 1) / max(1, count - 1)) for i in range(count)}):
            chosen.append((bench,) + heads[p])
    out = tempfile.mkdtemp()
    stages, walls, totals, rss_all = {}, [], [], []
    first = chosen[0]
    timed([binary, "register", "-s", f"{fragments}/fragment-{first[2]}", "-t",
           f"{fragments}/fragment-{first[1]}"] + args)  # warm-up
    per_pair = {}
    for run in range(runs):
        for bench, i, j in chosen:
            result = f"{out}/r.json"
            _, wall, rss = timed([binary, "register", "-s", f"{fragments}/fragment-{j}", "-t",
                                  f"{fragments}/fragment-{i}", "--out", result] + args)
            r = json.load(open(result))["result"]
            for stage, ms in r["timings_ms"].items():
                stages.setdefault(stage, []).append(ms)
            walls.append(wall)
            totals.append(r["timings_ms"]["total"])
            rss_all.append(rss)
            per_pair.setdefault((bench, i, j), []).append((wall, r["timings_ms"]["total"], rss,
                                                           r["path"], r["valid"]))
    print(f"{len(chosen)} fragment pairs x {runs} runs, options: {' '.join(args) or '(none)'}")
    print("median wall time per stage of `zeroreg register` (ms, timings_ms):")
    for stage, values in stages.items():
        print(f"  {stage:14s} {median(values):8.1f}   (min {min(values):.1f}, max {max(values):.1f})")
    print(f"\n  {'pair':22s} {'process s':>9s} {'in-process s':>12s} {'RSS MiB':>7s}  path, verdict")
    for (bench, i, j), rows in per_pair.items():
        print(f"  {bench + ' ' + str(j) + ' -> ' + str(i):22s} {median([w for w, *_ in rows]):9.2f} "
              f"{median([t for _, t, *_ in rows]) / 1000:12.2f} {max(r for _, _, r, *_ in rows):7.0f}"
              f"  {rows[0][3]}, {'valid' if rows[0][4] else 'invalid'}")
    print(f"  {'all (median)':22s} {median(walls):9.2f} {median(totals) / 1000:12.2f} "
          f"{max(rss_all):7.0f}")
    print(f"load average now {os.getloadavg()[0]:.1f}")
else:
    sys.exit(f"bench-speed.sh: unknown mode '{mode}'; expected pairs, eval or fragments")
PY
