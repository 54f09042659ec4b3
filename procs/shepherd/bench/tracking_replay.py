#!/usr/bin/env python3
"""tools/ephor bench tracking: id switches of the world model, replayed from recorded runs.

A live run cannot be repeated (real time), so a change to the world model
cannot be judged by running again. This replays the BLOBS of each recording
through a freshly started ephor-worldmodel (tools/ephor replay --procs
worldmodel: deterministic, seconds per 10-minute run) and scores the id
switches of its OBJECTS against the recording's GROUND_TRUTH as the run
monitor does (each visible sheep matched to the nearest live object within
40 mm; a sheep whose object changes is one switch). Beside it, the same score
of the OBJECTS the live run published.

Recordings: `tools/ephor bench herd ... --keep DIR` (DIR/*.lcm), or
`tools/ephor run deploy/shepherd.pbtxt --record F.lcm --record-channels
'BLOBS|OBJECTS|GROUND_TRUTH'`.

  tools/ephor bench tracking runs/*.lcm
  tools/ephor bench tracking runs/*.lcm --worldmodel-arg=--max-obscured-s=30 --json t.json
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

ROOT = os.environ.get("EPHOR_ROOT", os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))))
BIN = os.environ.get("EPHOR_BIN", os.path.join(ROOT, "build", "bin"))
MATCH_RADIUS_MM = 40.0  # RunMonitor's default (procs/shared/monitor/run_monitor.h)
DEAD = 2  # shepherd_object_t.STATE_DEAD


def export(log, channel, out):
    subprocess.run([os.path.join(BIN, "ephor-log"), "export", log, "--channel", channel, "--json",
                    "--out", out], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    with open(out) as f:
        return [json.loads(line)["msg"] for line in f]


def id_switches(truths, objects):
    """RunMonitor's id-switch score: (time s, sheep, old object, new object, x mm, y mm) per switch."""
    by_utime = {t["utime"]: t for t in truths}
    matched, switches = {}, []
    for o in objects:
        t = by_utime.get(o["utime"])
        if t is None:
            continue
        for s in t["sheep"]:
            if not s["on_field"]:
                matched.pop(s["id"], None)  # re-enters as a new sheep for the tracker
                continue
            if not s["visible"]:
                continue
            best, best_d = None, MATCH_RADIUS_MM
            for ob in o["objects"]:
                if ob["state"] == DEAD:
                    continue
                d = math.hypot(ob["x_mm"] - s["x_mm"], ob["y_mm"] - s["y_mm"])
                if d <= best_d:
                    best, best_d = ob, d
            if best is None:
                continue
            old = matched.get(s["id"])
            if old is not None and old != best["id"]:
                switches.append((round(t["sim_time_s"], 1), s["id"], old, best["id"],
                                 round(s["x_mm"]), round(s["y_mm"])))
            matched[s["id"]] = best["id"]
    return switches


def replay(log, tmp, worldmodel_args):
    out = os.path.join(tmp, "replayed.lcm")
    cmd = [os.path.join(ROOT, "tools", "ephor"), "replay", log, "--procs", "worldmodel", "--out", out]
    for a in worldmodel_args:
        cmd.append(f"--worldmodel-arg={a}")
    if os.geteuid() == 0:  # a private network namespace: nothing else can hear the replay
        cmd = [os.path.join(ROOT, "tools", "netns-run")] + cmd
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"replay of {log} failed (exit {r.returncode}): {r.stdout[-2000:]}")
    events = [line.split("] ", 2)[-1] for line in r.stdout.splitlines() if " born at " in line or " dead: " in line]
    return out, events


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("logs", nargs="+", help="recorded runs (LCM logs with BLOBS, OBJECTS, GROUND_TRUTH)")
    ap.add_argument("--worldmodel-arg", action="append", default=[],
                    help="extra ephor-worldmodel argument for the replay (repeatable)")
    ap.add_argument("--events", action="store_true", help="also print the world model's births and deaths")
    ap.add_argument("--json", help="write the per-run results here")
    ap.error = lambda message: ap.exit(2, f"{ap.prog}: error: {message}\n")
    args = ap.parse_args()
    for log in args.logs:
        if not os.path.isfile(log):
            ap.error(f"{log}: no such file")
    if not os.path.exists(os.path.join(BIN, "ephor-log")):
        ap.error(f"no {BIN}/ephor-log: build first (tools/ephor build)")

    results, total_live, total_replayed = [], 0, 0
    print("| run | id switches, live | id switches, replayed |")
    print("|---|---|---|")
    for log in args.logs:
        with tempfile.TemporaryDirectory() as tmp:
            truths = export(log, "GROUND_TRUTH", os.path.join(tmp, "truth.jsonl"))
            if not truths:
                ap.exit(2, f"{log}: no GROUND_TRUTH messages (record them with the run)\n")
            live = id_switches(truths, export(log, "OBJECTS", os.path.join(tmp, "live.jsonl")))
            replayed_log, events = replay(log, tmp, args.worldmodel_arg)
            replayed = id_switches(truths, export(replayed_log, "OBJECTS", os.path.join(tmp, "objects.jsonl")))
        total_live += len(live)
        total_replayed += len(replayed)
        print(f"| {os.path.basename(log)} | {len(live)} | {len(replayed)} |", flush=True)
        for sw in replayed:
            print("    switch at %.1f s: sheep %d, object %d -> %d at (%d, %d) mm" % sw)
        if args.events:
            for e in events:
                print("    " + e)
        results.append({"log": log, "id_switches_live": len(live), "id_switches_replayed": len(replayed),
                        "switches": [dict(zip(("t_s", "sheep", "from", "to", "x_mm", "y_mm"), sw)) for sw in replayed]})
    print(f"| all {len(args.logs)} | {total_live} | {total_replayed} |")
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"worldmodel_args": args.worldmodel_arg, "runs": results,
                       "id_switches_live": total_live, "id_switches_replayed": total_replayed}, f, indent=1)


if __name__ == "__main__":
    try:
        main()
    except (RuntimeError, subprocess.CalledProcessError) as e:
        sys.stderr.write(f"bench tracking: {e}\n")
        sys.exit(1)
