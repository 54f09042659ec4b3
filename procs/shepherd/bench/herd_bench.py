#!/usr/bin/env python3
"""tools/ephor bench herd: whole-system confinement, the shepherding table.

Runs the whole shepherding system headless (real processes, real time: the
launcher, both schedulers, sim, vision, world model, planner, comm, arm and
monitor) once per cell of sheep counts x planners x seeds, each for --minutes,
and writes escapes, saves, id switches and frame-to-arm-command latency per
cell. Each run has its own private network namespace (tools/netns-run, needs
root; --no-netns otherwise), so runs going at once (--parallel N, or another
bench herd) cannot hear each other. One run uses about a fifth of a core
here, but latency figures are cleanest with --parallel 1 on a quiet machine.

  tools/ephor bench herd --json herd.json                      # 2,4,6,8 sheep x multi,lookahead x 10 min
  tools/ephor bench herd --sheep 4 --seeds 1,2,3 --sheep-speed 20 --json f.json
  tools/ephor bench herd --sheep 4 --sim-arg=--clouds=2 --json clouds.json
  tools/ephor bench herd --sheep 8 --seeds 1,2,3 --keep runs/    # and keep each run's log and recording

The default table (8 runs of 10 minutes) takes about 80 minutes with
--parallel 1: a benchmark, not a test.
"""
import argparse
import concurrent.futures
import json
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.environ.get("EPHOR_ROOT", os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))))
BIN = os.environ.get("EPHOR_BIN", os.path.join(ROOT, "build", "bin"))

# Paper 003, section 4.1 and figure 21: four Lego sheep at 2-3 px/s were kept
# "for a limited amount of time, about two saves each".
PAPER = {"sheep": 4, "sheep_speed_mm_s": "5.4-8.1", "saves_per_sheep": 2,
         "kept": "for a limited amount of time"}


def int_list(text):
    try:
        values = [int(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a comma-separated list of integers")
    if not values or min(values) < 0:
        raise argparse.ArgumentTypeError(f"'{text}': give one or more integers >= 0")
    return values


def run_cell(cell, args):
    """One whole-system run; returns the cell with the monitor's summary."""
    with tempfile.TemporaryDirectory() as tmp:
        summary = os.path.join(tmp, "summary.json")
        cmd = [os.path.join(BIN, "ephor-launch"), os.path.join(ROOT, "deploy", "shepherd.pbtxt"),
               "--headless", "--duration", str(int(args.minutes * 60)),
               "--seed", str(cell["seed"]), "--sheep", str(cell["sheep"]),
               "--planner", cell["planner"], "--sheep-speed", str(args.sheep_speed),
               "--summary", summary]
        for a in args.sim_arg:
            cmd += ["--arg", f"sim={a}"]
        name = f"sheep{cell['sheep']}_{cell['planner']}_seed{cell['seed']}"
        if args.keep:
            # Small enough to keep for every run (~4 MB a minute): what the tracker saw and
            # did, the truth to score it and the arm; `tools/ephor replay FILE --procs
            # worldmodel` reruns a changed world model over it.
            cmd += ["--record", os.path.join(args.keep, name + ".lcm"),
                    "--record-channels", "BLOBS|OBJECTS|GROUND_TRUTH|ARM_STATE|ARM_GOAL"]
        if not args.no_netns:
            cmd = [os.path.join(ROOT, "tools", "netns-run")] + cmd
        t0 = time.monotonic()
        log = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        if args.keep:
            with open(os.path.join(args.keep, name + ".log"), "w") as f:
                f.write(log.stdout)
        if log.returncode != 0 or not os.path.exists(summary):
            sys.stderr.write(log.stdout[-4000:])
            return dict(cell, error=f"run failed (exit {log.returncode})")
        with open(summary) as f:
            s = json.load(f)
    return dict(cell, wall_s=round(time.monotonic() - t0, 1), escapes=s.get("escapes"),
                saves=s.get("saves"), id_switches=s.get("id_switches"),
                latency_ms=s.get("latency_ms"), deadline_misses=s.get("deadline_misses"),
                rt=s.get("rt"), duration_s=s.get("duration_s"),
                vision_rate_hz=s.get("vision_rate_hz"))


def row(r):
    if "error" in r:
        return f"| {r['sheep']} | {r['planner']} | {r['seed']} | {r['error']} | | | | |"
    lat = r.get("latency_ms") or {}
    return (f"| {r['sheep']} | {r['planner']} | {r['seed']} | {r['escapes']} | {r['saves']} | "
            f"{r['id_switches']} | {lat.get('p50', float('nan')):.2f} / {lat.get('p99', float('nan')):.2f} | "
            f"{r['deadline_misses']} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sheep", type=int_list, default=[2, 4, 6, 8], help="sheep counts (default 2,4,6,8)")
    ap.add_argument("--planners", default="multi,lookahead", help="planners (default multi,lookahead)")
    ap.add_argument("--seeds", type=int_list, default=[1], help="seeds (default 1)")
    ap.add_argument("--minutes", type=float, default=10.0, help="minutes per run (default 10)")
    ap.add_argument("--sheep-speed", type=float, default=8.0, help="nominal sheep speed, mm/s (default 8)")
    ap.add_argument("--sim-arg", action="append", default=[], help="extra ephor-sim argument (repeatable)")
    ap.add_argument("--parallel", type=int, default=1, help="runs at once")
    ap.add_argument("--no-netns", action="store_true",
                    help="run on the host's network instead of a private namespace per run (needs no "
                         "root, but then no other LCM run may be going on at the same time)")
    ap.add_argument("--json", help="write the cells here")
    ap.add_argument("--keep", metavar="DIR",
                    help="keep each run's output (DIR/CELL.log: escapes, id switches, the world model's "
                         "births and deaths) and a recording of its non-camera channels (DIR/CELL.lcm)")
    # A bad flag: one line naming it and status 2, without the usage block (issue 18).
    ap.error = lambda message: ap.exit(2, f"{ap.prog}: error: {message}\n")
    args = ap.parse_args()
    planners = [p for p in args.planners.split(",") if p]
    for p in planners:
        if p not in ("single", "multi", "lookahead"):
            ap.error(f"unknown planner '{p}' (single, multi, lookahead)")
    if not (0 < args.minutes <= 600):
        ap.error("--minutes must be in (0, 600]")
    if not (0 < args.sheep_speed <= 1000):
        ap.error("--sheep-speed must be in (0, 1000] mm/s")
    if not (1 <= args.parallel <= 8):
        ap.error("--parallel must be in [1, 8]")
    if not os.path.exists(os.path.join(BIN, "ephor-launch")):
        ap.error(f"no {BIN}/ephor-launch: build first (tools/ephor build)")

    if args.keep:
        os.makedirs(args.keep, exist_ok=True)
    cells = [{"sheep": n, "planner": p, "seed": s} for n in args.sheep for p in planners for s in args.seeds]
    print(f"bench herd: {len(cells)} run(s) of {args.minutes:g} min at {args.sheep_speed:g} mm/s, "
          f"{args.parallel} at a time; sim args {args.sim_arg}", flush=True)
    print("| sheep | planner | seed | escapes | saves | id switches | latency p50 / p99 ms | deadline misses |")
    print("|---|---|---|---|---|---|---|---|", flush=True)
    results = []
    with concurrent.futures.ThreadPoolExecutor(max_workers=args.parallel) as pool:
        for r in pool.map(lambda c: run_cell(c, args), cells):
            results.append(r)
            print(row(r), flush=True)
    out = {"paper": PAPER, "minutes": args.minutes, "sheep_speed_mm_s": args.sheep_speed,
           "sim_args": args.sim_arg, "parallel": args.parallel, "cells": results}
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=1)
    return 1 if any("error" in r for r in results) else 0


if __name__ == "__main__":
    sys.exit(main())
