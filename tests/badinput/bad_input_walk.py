#!/usr/bin/env python3
"""Bad input at the edges a person touches (issue 18, item 5).

Walks every ephor executable the build lists (CMake writes the list, so a new
process is covered without editing this file) and every `tools/ephor`
subcommand, giving each an unknown flag, a flag without its value, an
out-of-range number, a missing file and a directory where it reads a file.
Each must answer with exit status 2 and one line on stderr that names the
problem: no stack trace, no abort, no core, and no start (a process still
running after TIMEOUT_S is killed and counted as a failure).

  bad_input_walk.py EXECUTABLES.txt GBENCH_EXECUTABLES.txt SOURCE_DIR

Flags without a value and ranged numbers are read from each --help (CLI11's
"INT:INT in [a - b]", POSITIVE, NONNEGATIVE), so they follow the code.
The files each program reads are the table FILE_INPUTS below: a new program
must be added there (with [] when it reads none) or this test fails.
"""

import os
import re
import signal
import subprocess
import sys
import tempfile

TIMEOUT_S = 3.0

# Files (not folders) each program reads: a flag, or None for the positional
# argument. Output files are not listed: a bad output path is reported only
# when the program writes it.
FILE_INPUTS = {
    "ephor-arm": ["--calibration", "--workcell"],
    "ephor-bench-planner": ["--start"],
    "ephor-bench-predict": [],
    "ephor-bench-rambo": [],
    "ephor-bench-sched": [],
    "ephor-bench-sphere": [],
    "ephor-bench-sphere-approach": [],
    "ephor-bench-stripe": [],  # --scenes is a folder
    "ephor-bench-vision": [],
    "ephor-calibrate": [],
    "ephor-camera": [None],
    "ephor-catch-display": [],
    "ephor-catch-monitor": [],
    "ephor-catch-prim": ["--board"],
    "ephor-catch-harness": ["--board", "--workcell"],
    "ephor-catch-loop": ["--board", "--workcell"],
    "ephor-catch-sim": ["--board", "--workcell"],
    "ephor-catch-track": [None, "--board", "--camera"],
    "ephor-catch-vision": ["--board", "--camera"],
    "ephor-catch-worldmodel": ["--board", "--camera"],
    "ephor-comm": [],
    "ephor-deputy": [],
    "ephor-display": ["--calibration"],
    "ephor-e2e-probe": [],
    "ephor-launch": [None],
    "ephor-log": [],  # its subcommands. files: the tools/ephor log cases
    "ephor-make-sim-calibration": [],
    "ephor-monitor": [],
    "ephor-planner": ["--calibration", "--workcell"],
    "ephor-rambo-features": [],
    "ephor-rambo-planner": [],
    "ephor-rambo-pose": [],
    "ephor-rambo-predictor": [],
    "ephor-rambo-display": ["--model"],
    "ephor-rambo-sim": ["--workcell"],
    "ephor-replay": [None],
    "ephor-scheduler": ["--manifest"],
    "ephor-sheriff": [None],
    "ephor-sim": ["--config", "--workcell"],
    "ephor-sphere-display": [],
    "ephor-sphere-guidance": [],
    "ephor-sphere-locate": [None],
    "ephor-sphere-locator": [],
    "ephor-sphere-ranger": [],
    "ephor-sphere-scan": [],
    "ephor-stripe-calibrate": ["--from", "--workcell"],
    "ephor-stripe-display": [],
    "ephor-stripe-planner": ["--calibration", "--scene", "--workcell"],
    "ephor-stripe-range": ["--calibration", "--workcell"],
    "ephor-stripe-sim": ["--scene", "--workcell"],
    "ephor-stripe-stripe": [],
    "ephor-testtask": [],
    "ephor-track": [None],
    "ephor-vision": [],
    "ephor-worldmodel": ["--calibration", "--workcell"],
}

# Arguments a program requires before anything else is looked at; the bad
# input is added to them. Files named here do exist (repository files), so the
# one being tested is the only bad one.
def base_args(src):
    board = os.path.join(src, "deploy/catch/board.pbtxt")
    camera = os.path.join(src, "deploy/catch/camera.pbtxt")
    return {
        "ephor-camera": ["video.avi"],
        "ephor-catch-track": ["video.avi", "--board", board, "--camera", camera,
                              "--fps", "30", "--json", "-"],
        "ephor-launch": [os.path.join(src, "deploy/shepherd.pbtxt")],  # flags may be its parameters
        "ephor-log": ["info", os.path.join(src, "README.md")],  # an existing file
        "ephor-make-sim-calibration": ["--out", "out.pbtxt"],
        "ephor-replay": [os.path.join(src, "README.md")],  # an existing file
        "ephor-scheduler": ["--manifest", "manifest.pbtxt"],
        "ephor-sheriff": [os.path.join(src, "deploy/shepherd.pbtxt")],  # flags may be its parameters
        "ephor-sphere-locate": ["scan.csv", "--json", "-"],
        "ephor-sphere-scan": ["--out", "scan.csv"],
        "ephor-stripe-calibrate": ["--out", "out.pbtxt"],
        "ephor-testtask": ["--task", "periodic:t:10"],
        "ephor-track": ["video.avi", "--json", "-"],
    }

# Programs that do not follow the rule yet, each with the reason: their cases
# are run and reported but do not fail the test. Remove an entry once fixed.
_OTHERS_EDITING = "its folder was being rewritten when this walk was added (issue 18, item 5 open for it)"
KNOWN_FAILURES = {
}

TRACE_MARKS = ["terminate called", "what():", "Aborted", "core dumped", "Segmentation fault",
               "Traceback (most recent call last)", "stack trace", "Stack trace", "AddressSanitizer",
               "runtime error:"]

VALUE_OPTION = re.compile(r"^\s+(--[\w-]+)(?:,--?[\w-]+)*\s+(TEXT|INT|UINT|FLOAT)\b(?!.*\.\.\.)(?!\s+x\s+\d)")
RANGE_OPTION = re.compile(
    r"^\s+(--[\w-]+)(?:,--?[\w-]+)*\s+(INT|UINT|FLOAT):(?:INT|UINT|FLOAT) in \[(\S+) - (\S+)\]")
SIGN_OPTION = re.compile(r"^\s+(--[\w-]+)(?:,--?[\w-]+)*\s+(INT|UINT|FLOAT):(POSITIVE|NONNEGATIVE)")
COMMON_FLAGS = {"--name", "--host", "--lcm-url"}


def run(argv, cwd, env):
    """Runs argv; returns (status or None when it had to be killed, stderr)."""
    proc = subprocess.Popen(argv, cwd=cwd, env=env, stdin=subprocess.DEVNULL,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                            start_new_session=True)
    try:
        _, err = proc.communicate(timeout=TIMEOUT_S)
        return proc.returncode, err.decode(errors="replace")
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        _, err = proc.communicate()
        return None, err.decode(errors="replace")


def judge(status, err, names):
    """The problem with one answer, or None when it follows the rule."""
    lines = [line for line in err.splitlines() if line.strip()]
    if status is None:
        return f"still running after {TIMEOUT_S:.0f} s (started instead of refusing)"
    if status < 0:
        return f"killed by signal {-status} ({signal.Signals(-status).name})"
    for mark in TRACE_MARKS:
        if mark in err:
            return f"stderr has '{mark}'"
    if status != 2:
        return f"exit status {status}, not 2"
    if len(lines) != 1:
        return f"{len(lines)} lines on stderr, not 1"
    if names and not any(n in lines[0] for n in names):
        return f"the error does not name {' or '.join(repr(n) for n in names)}"
    return None


def help_text(exe, cwd, env):
    try:
        out = subprocess.run([exe, "--help"], cwd=cwd, env=env, stdin=subprocess.DEVNULL,
                             capture_output=True, timeout=TIMEOUT_S)
        return out.stdout.decode(errors="replace")
    except subprocess.TimeoutExpired:
        return ""


def out_of_range(kind, lo, hi):
    """A value just outside [lo, hi] in the option's own type."""
    hi_v = float(hi)
    v = hi_v + max(1.0, abs(hi_v))
    if kind in ("INT", "UINT"):
        return str(int(v))
    return repr(v)


def executable_cases(exe, src, tmp):
    """(label, argv, names the error must contain) for one program."""
    name = os.path.basename(exe)
    base = base_args(src).get(name, [])
    env = dict(os.environ)
    cases = [("unknown flag", [exe] + base + ["--no-such-flag"], ["--no-such-flag"])]
    text = help_text(exe, tmp, env)
    valued, ranged = [], []
    for line in text.splitlines():
        m = VALUE_OPTION.match(line)
        if m:
            valued.append(m.group(1))
        m = RANGE_OPTION.match(line)
        if m:
            ranged.append((m.group(1), out_of_range(m.group(2), m.group(3), m.group(4))))
        m = SIGN_OPTION.match(line)
        if m:
            ranged.append((m.group(1), "-1"))
    own = [f for f in valued if f not in COMMON_FLAGS and f not in base]
    flag = (own or valued or [None])[0]
    if flag:
        cases.append((f"{flag} without its value", [exe] + base + [flag], [flag]))
    else:
        cases.append(("flag without its value", None, "its --help lists no option with a value"))
    if ranged:
        flag, value = ranged[0]
        cases.append((f"{flag} {value} (out of range)", [exe] + base + [flag, value], [flag]))
    missing = os.path.join(tmp, "no-such-file.pbtxt")
    folder = os.path.join(tmp, "a-folder")
    for inp in FILE_INPUTS.get(name, []):
        for what, path in (("missing file", missing), ("a directory", folder)):
            if inp is None:
                argv = [exe, path] + base[1:]
                label = f"{what} as {{positional}}"
            elif inp in base:  # the flag is required: replace its value
                i = base.index(inp)
                argv = [exe] + base[:i + 1] + [path] + base[i + 2:]
                label = f"{what} for {inp}"
            else:
                argv = [exe] + base + [inp, path]
                label = f"{what} for {inp}"
            cases.append((label, argv, [path]))
    return cases


def ephor_cases(src, tmp):
    """tools/ephor and its subcommands (tools/ephor.d)."""
    existing = os.path.join(src, "README.md")  # a file that exists: the flag is the bad input
    e = os.path.join(src, "tools/ephor")
    missing = os.path.join(tmp, "no-such-file.pbtxt")
    folder = os.path.join(tmp, "a-folder")
    manifest = os.path.join(src, "deploy/shepherd.pbtxt")
    return [
        ("unknown subcommand", [e, "no-such-subcommand"], ["no-such-subcommand"]),
        ("unknown flag", [e, "--no-such-flag"], ["--no-such-flag"]),
        ("setup: unknown flag", [e, "setup", "--no-such-flag"], ["--no-such-flag"]),
        ("build: unknown flag", [e, "build", "--no-such-flag"], ["--no-such-flag"]),
        ("sanitize: unknown flag", [e, "sanitize", "--no-such-flag"], ["--no-such-flag"]),
        ("demo: unknown system", [e, "demo", "no-such-system"], ["no-such-system"]),
        ("run: no manifest", [e, "run"], ["MANIFEST"]),
        ("run: missing file", [e, "run", missing], [missing]),
        ("run: a directory", [e, "run", folder], [folder]),
        ("run: unknown flag", [e, "run", manifest, "--no-such-flag"], ["--no-such-flag"]),
        ("run: --duration without its value", [e, "run", manifest, "--duration"], ["--duration"]),
        ("run: --duration -1", [e, "run", manifest, "--duration", "-1"], ["--duration"]),
        ("bench: unknown name", [e, "bench", "no-such-bench"], ["no-such-bench"]),
        ("bench sched: unknown flag", [e, "bench", "sched", "--no-such-flag"], ["--no-such-flag"]),
        ("bench confine: --seeds 0", [e, "bench", "confine", "--seeds", "0"], ["--seeds"]),
        ("bench herd: unknown flag", [e, "bench", "herd", "--no-such-flag"], ["--no-such-flag"]),
        ("bench catch: unknown flag", [e, "bench", "catch", "--no-such-flag"], ["--no-such-flag"]),
        ("calibrate: --out without its value", [e, "calibrate", "--out"], ["--out"]),
        ("calibrate: unknown flag", [e, "calibrate", "--no-such-flag"], ["--no-such-flag"]),
        ("calibrate: --speed 5", [e, "calibrate", "--speed", "5"], ["--speed"]),
        ("log: unknown command", [e, "log", "no-such-command"], ["no-such-command"]),
        ("log record: unknown flag", [e, "log", "record", "--no-such-flag"], ["--no-such-flag"]),
        ("log play: missing file", [e, "log", "play", missing], [missing]),
        ("log play: a directory", [e, "log", "play", folder], [folder]),
        ("log play: --speed without its value", [e, "log", "play", missing, "--speed"], ["--speed"]),
        ("log info: missing file", [e, "log", "info", missing], [missing]),
        ("log info: a directory", [e, "log", "info", folder], [folder]),
        ("log export: missing file", [e, "log", "export", missing, "--channel", "BLOBS", "--json"],
         [missing]),
        ("plot: unknown flag", [e, "plot", missing, "--out", tmp, "--no-such-flag"],
         ["--no-such-flag"]),
        ("plot: missing file", [e, "plot", missing, "--out", tmp], [missing]),
        ("plot: a directory", [e, "plot", folder, "--out", tmp], [folder]),
        ("plot: --objects without its value", [e, "plot", missing, "--out", tmp, "--objects"],
         ["--objects"]),
        ("spy: unknown flag", [e, "spy", "--no-such-flag"], ["--no-such-flag"]),
        ("spy: --timeout-s without its value", [e, "spy", "--timeout-s"], ["--timeout-s"]),
        ("replay: unknown flag", [e, "replay", existing, "--no-such-flag"], ["--no-such-flag"]),
        ("replay: missing file", [e, "replay", missing], [missing]),
        ("replay: a directory", [e, "replay", folder], [folder]),
        ("replay: --timeout-s 0", [e, "replay", existing, "--timeout-s", "0"], ["--timeout-s"]),
        ("track: unknown flag", [e, "track", missing, "--json", "-", "--no-such-flag"],
         ["--no-such-flag"]),
        ("track: missing file", [e, "track", missing, "--json", "-"], [missing]),
        ("track: a directory", [e, "track", folder, "--json", "-"], [folder]),
        ("catch: unknown command", [e, "catch", "no-such-command"], ["no-such-command"]),
        ("catch track: unknown flag",
         [e, "catch", "track"] + base_args(src)["ephor-catch-track"] + ["--no-such-flag"],
         ["--no-such-flag"]),
        ("sphere: unknown command", [e, "sphere", "no-such-command"], ["no-such-command"]),
        ("sphere locate: missing file", [e, "sphere", "locate", missing, "--json", "-"], [missing]),
        ("sphere locate: a directory", [e, "sphere", "locate", folder, "--json", "-"], [folder]),
        ("sphere scan: --distance-m 0", [e, "sphere", "scan", "--distance-m", "0", "--out", "x.csv"],
         ["--distance-m"]),
        ("fuzz: unknown flag", [e, "fuzz", "--no-such-flag"], ["--no-such-flag"]),
        ("fuzz: unknown target", [e, "fuzz", "no-such-target"], ["no-such-target"]),
        ("fuzz: --seconds without its value", [e, "fuzz", "manifest", "--seconds"], ["--seconds"]),
        ("fuzz: --runs 0", [e, "fuzz", "manifest", "--runs", "0"], ["--runs"]),
        ("deputy: unknown flag", [e, "deputy", "--no-such-flag"], ["--no-such-flag"]),
        ("deputy: --grace -1", [e, "deputy", "--grace", "-1"], ["--grace"]),
        ("sheriff: missing file", [e, "sheriff", missing], [missing]),
        ("sheriff: a directory", [e, "sheriff", folder], [folder]),
        ("sheriff: unknown flag", [e, "sheriff", manifest, "--no-such-flag"], ["--no-such-flag"]),
    ]


# Subcommands not walked, with the reason (each is reached another way).
EPHOR_NOT_WALKED = {
    "test": "its flags are ctest's, passed on after a build (tools/ephor build is walked)",
}


def read_list(path):
    with open(path) as f:
        return sorted({line.strip() for line in f if line.strip()})


def main():
    exes_file, gbench_file, src = sys.argv[1:4]
    exes = read_list(exes_file)
    gbench = set(read_list(gbench_file))
    failures, known, passed = [], [], 0
    with tempfile.TemporaryDirectory(prefix="ephor-badinput-") as tmp:
        os.mkdir(os.path.join(tmp, "a-folder"))
        env = dict(os.environ)
        env["EPHOR_BUILD_DIR"] = os.path.dirname(os.path.dirname(exes[0]))
        env["EPHOR_BIN"] = os.path.dirname(exes[0])
        walks = []
        for exe in exes:
            name = os.path.basename(exe)
            if exe in gbench:
                print(f"skip {name}: a Google Benchmark binary (its flags are the library's)")
                continue
            if not os.access(exe, os.X_OK):
                failures.append(f"{name}: not built ({exe})")
                continue
            if name not in FILE_INPUTS and name not in KNOWN_FAILURES:
                failures.append(f"{name}: not in FILE_INPUTS of {__file__}: list the files it "
                                "reads ([] when none)")
            walks += [(name, c) for c in executable_cases(exe, src, tmp)]
        if any(f.endswith(": not built") or "not built (" in f for f in failures):
            # tools/ephor builds a missing program first: never from a test.
            failures.append("tools/ephor: not walked, as some programs are not built")
        else:
            walks += [("tools/ephor", c) for c in ephor_cases(src, tmp)]
        for sub, why in EPHOR_NOT_WALKED.items():
            print(f"skip tools/ephor {sub}: {why}")
        for who, (label, argv, names) in walks:
            if argv is None:
                failures.append(f"{who}: {label}: {names}")
                continue
            status, err = run(argv, tmp, env)
            problem = judge(status, err, names)
            shown = err.strip().splitlines()
            first = shown[0] if shown else "(no stderr)"
            if problem is None:
                passed += 1
                print(f"ok   {who}: {label}: {first}")
                continue
            text = f"{who}: {label}: {problem}; stderr: {first[:200]}"
            if who in KNOWN_FAILURES:
                known.append(f"{text} [known: {KNOWN_FAILURES[who]}]")
            else:
                failures.append(text)
    for k in known:
        print(f"KNOWN FAILURE {k}")
    for f in failures:
        print(f"FAIL {f}")
    print(f"{passed} cases follow the rule, {len(known)} known failures, {len(failures)} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
