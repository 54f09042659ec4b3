#!/usr/bin/env python3
"""tools/ephor bench catch: the catching system's figures beside the paper's (seed 000).

Runs the whole system headless (real processes, real time) for --seeds seeds x
--balls balls, each run a `ephor-launch deploy/catch.pbtxt --headless` with a
JSON summary, and the component benchmarks (Google Benchmark executables):
vision (frame differencing full frame and windowed, MOG2 peer, circles, IPPE
against iterative solvePnP), world model, simulator. Writes one JSON (--json)
and prints the tables of README.md's catching section.

The default (5 seeds x 100 balls) takes about 30 minutes: a benchmark, not a test.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.environ.get("EPHOR_ROOT", os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))))
BIN = os.environ.get("EPHOR_BIN", os.path.join(ROOT, "build", "bin"))

# Paper 000, Table 1 and section 6 (68020 boards, PIPE), ms.
PAPER = {"L2 EX": 0.7, "L1 EX": 0.7, "PIPE manager": 63.0, "L2 SP": 0.5, "L2 WM": 1.9,
         "update": 66.8, "throughput": 100.2}


def run_system(seed, balls, timeout_s):
    with tempfile.TemporaryDirectory() as tmp:
        summary = os.path.join(tmp, "summary.json")
        cmd = [os.path.join(BIN, "ephor-launch"), os.path.join(ROOT, "deploy", "catch.pbtxt"),
               "--headless", "--seed", str(seed), "--balls", str(balls), "--summary", summary,
               "--duration", str(timeout_s)]
        log = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        if log.returncode != 0 or not os.path.exists(summary):
            sys.stderr.write(log.stdout[-4000:])
            raise SystemExit(f"bench catch: the run with seed {seed} failed (exit {log.returncode})")
        with open(summary) as f:
            return json.load(f)


def run_benchmark(name, filt=None):
    exe = os.path.join(BIN, name)
    if not os.path.exists(exe):
        return {"error": f"{name} not built"}
    cmd = [exe, "--benchmark_format=json", "--benchmark_repetitions=3",
           "--benchmark_report_aggregates_only=true"]
    if filt:
        cmd.append(f"--benchmark_filter={filt}")
    out = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True, check=True)
    data = json.loads(out.stdout)
    result = {}
    for b in data["benchmarks"]:
        if b.get("aggregate_name") != "median":
            continue
        unit = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}[b["time_unit"]]
        result[b["run_name"]] = round(b["cpu_time"] * unit, 4)
    return result


def weighted(runs, key, stat):
    vals = [r[key][stat] for r in runs if r[key].get(stat) is not None]
    return max(vals) if stat == "p99" else (sorted(vals)[len(vals) // 2] if vals else None)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seeds", type=int, default=5, help="seeds 1..N (default 5)")
    ap.add_argument("--balls", type=int, default=100, help="balls per seed (default 100)")
    ap.add_argument("--json", help="write the figures here")
    ap.add_argument("--no-system", action="store_true", help="only the component benchmarks")
    # A bad flag: one line naming it and status 2, without the usage block (issue 18).
    ap.error = lambda message: ap.exit(2, f"{ap.prog}: error: {message}\n")
    args = ap.parse_args()
    if args.seeds < 1 or args.balls < 1:
        ap.error("--seeds and --balls must be >= 1")

    out = {"paper_ms": PAPER, "components_ms": {}, "runs": []}
    for name in ("ephor-bench-catch-vision", "ephor-bench-catch-worldmodel", "ephor-bench-catch-sim"):
        out["components_ms"][name] = run_benchmark(name)
        print(f"{name}: {json.dumps(out['components_ms'][name])}", flush=True)

    if not args.no_system:
        for seed in range(1, args.seeds + 1):
            s = run_system(seed, args.balls, timeout_s=args.balls * 6 + 60)
            out["runs"].append(s)
            print(f"seed {seed}: {s['balls']} balls, caught {s['caught']}, oracle-reachable "
                  f"{s['oracle_reachable']} (caught of those {s['caught_of_oracle_reachable']}), "
                  f"throughput p99 {s['throughput_ms']['p99']} ms, update p50 {s['update_ms']['p50']} ms, "
                  f"position error p50/p99 {s['position_error_mm']['p50']}/{s['position_error_mm']['p99']} mm, "
                  f"camera pose {s['camera_pose_error_mm']} mm {s['camera_pose_error_deg']} deg", flush=True)
        runs = out["runs"]
        balls = sum(r["balls"] for r in runs)
        caught = sum(r["caught"] for r in runs)
        reach = sum(r["oracle_reachable"] for r in runs)
        caught_reach = sum(r["caught_of_oracle_reachable"] for r in runs)
        out["total"] = {
            "balls": balls, "caught": caught, "oracle_reachable": reach,
            "caught_of_oracle_reachable": caught_reach,
            "catch_rate_of_reachable": (caught_reach / reach) if reach else None,
            "throughput_ms_p99_max": weighted(runs, "throughput_ms", "p99"),
            "update_ms_p50_median": weighted(runs, "update_ms", "p50"),
            "position_error_mm_p99_max": weighted(runs, "position_error_mm", "p99"),
            "position_error_mm_p50_median": weighted(runs, "position_error_mm", "p50"),
            "camera_pose_error_mm_max": max((r["camera_pose_error_mm"] or 0) for r in runs),
            "camera_pose_error_deg_max": max((r["camera_pose_error_deg"] or 0) for r in runs),
            "deadline_misses": sum(r["deadline_misses"] for r in runs),
        }
        print(json.dumps(out["total"], indent=2))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=2)
        print(f"written to {args.json}")


if __name__ == "__main__":
    main()
