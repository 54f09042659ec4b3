#!/usr/bin/env python3
"""tools/ephor bench rambo-tagging: RAMBO's laser tagging over many seeds (issue 17).

Runs the whole system headless (real processes, real time), one
`ephor-launch deploy/rambo.pbtxt --headless --seed S --diodes N --max_s M
--summary F` per seed, each in a private network namespace (tools/netns-run),
and reports per seed the diodes tagged, the time to tag all, the diodes
never tagged and the pose error; then the totals. The target: every diode
of every seed. Each seed's result is appended to --jsonl as it ends, so an
interrupted bench keeps what it measured. 20 seeds take 10-40 minutes: a
benchmark, not a test; run it with nice on a shared machine.
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.environ.get("EPHOR_ROOT", os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))))
BIN = os.environ.get("EPHOR_BIN", os.path.join(ROOT, "build", "bin"))


def diode_names():
    """The model file's diode names, in order (deploy/rambo/target.pbtxt)."""
    with open(os.path.join(ROOT, "deploy", "rambo", "target.pbtxt")) as f:
        return re.findall(r'^diode \{ name: "([^"]+)"', f.read(), re.M)


def run_seed(seed, diodes, max_s, features, extra, logs=None):
    with tempfile.TemporaryDirectory() as tmp:
        summary = os.path.join(tmp, "summary.json")
        cmd = [os.path.join(ROOT, "tools", "netns-run"), os.path.join(BIN, "ephor-launch"),
               os.path.join(ROOT, "deploy", "rambo.pbtxt"), "--headless", "--seed", str(seed),
               "--diodes", str(diodes), "--max_s", str(max_s), "--features_channel", features,
               "--summary", summary] + extra
        log = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                             cwd=ROOT)
        if logs:
            with open(os.path.join(logs, f"seed{seed}.log"), "w") as f:
                f.write(log.stdout)
        if not os.path.exists(summary):
            sys.stderr.write(log.stdout[-4000:])
            raise SystemExit(f"bench rambo-tagging: the run with seed {seed} wrote no summary "
                             f"(exit {log.returncode})")
        with open(summary) as f:
            s = json.load(f)
        s["trajectories_accepted"] = log.stdout.count("given trajectory move")
        s["point_to_point_moves"] = log.stdout.count("joint-space move") + log.stdout.count("cartesian move")
        return s


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--first-seed", type=int, default=1)
    ap.add_argument("--diodes", type=int, default=4)
    ap.add_argument("--max-s", type=float, default=120.0, help="end a seed's run after this long")
    ap.add_argument("--features", default="RAMBO_FEATURES",
                    help="RAMBO_FEATURES (images) or RAMBO_FEATURES_ORACLE")
    ap.add_argument("--arg", action="append", default=[], help="passed to ephor-launch as --arg")
    ap.add_argument("--jsonl", help="append each seed's summary here as it ends")
    ap.add_argument("--json", help="write all summaries and the totals here")
    ap.add_argument("--logs", help="keep each seed's run output (every process's log) in this "
                    "directory as seedS.log")
    a = ap.parse_args()
    if a.seeds < 1 or not 1 <= a.diodes <= 8 or a.max_s <= 0:
        print("bench rambo-tagging: --seeds >= 1, --diodes 1-8, --max-s > 0", file=sys.stderr)
        return 2
    extra = [x for arg in a.arg for x in ("--arg", arg)]
    if a.logs:
        os.makedirs(a.logs, exist_ok=True)
    runs = []
    print("seed  tagged  time to all s  not tagged                pose mm p50/p99  trajectories/p2p")
    for seed in range(a.first_seed, a.first_seed + a.seeds):
        s = run_seed(seed, a.diodes, a.max_s, a.features, extra, a.logs)
        runs.append(s)
        tagged = {t["name"] for t in s["tasks"]}
        missing = [n for n in diode_names()[:s["diodes"]] if n not in tagged]
        s["not_tagged"] = missing
        if a.jsonl:
            with open(a.jsonl, "a") as f:
                f.write(json.dumps(s) + "\n")
        pe = s.get("pose_error_mm") or {}
        t = s["time_to_all_s"]
        print(f"{seed:4d}  {s['tagged']}/{s['diodes']}  {t if t is None else round(t, 1)!s:>13}  "
              f"{','.join(missing) or '-':24s}  {pe.get('p50', float('nan')):.2f}/{pe.get('p99', float('nan')):.2f}"
              f"  {s['trajectories_accepted']}/{s['point_to_point_moves']}", flush=True)
    all_tagged = sum(1 for s in runs if s["tagged"] == s["diodes"])
    times = sorted(s["time_to_all_s"] for s in runs if s["time_to_all_s"] is not None)
    total = {"seeds": len(runs), "seeds_all_tagged": all_tagged,
             "diodes_tagged": sum(s["tagged"] for s in runs),
             "diodes": sum(s["diodes"] for s in runs),
             "time_to_all_s_p50": times[len(times) // 2] if times else None,
             "time_to_all_s_max": times[-1] if times else None}
    print(f"all diodes tagged in {all_tagged} of {len(runs)} seeds; {total['diodes_tagged']} of "
          f"{total['diodes']} diodes; time to all p50 {total['time_to_all_s_p50']} s, "
          f"max {total['time_to_all_s_max']} s")
    if a.json:
        with open(a.json, "w") as f:
            json.dump({"runs": runs, "total": total}, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
