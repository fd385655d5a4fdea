#!/usr/bin/python3
"""kill -9 at random moments of `aggkit scan`, `aggkit sweep` and `aggkit validate`, then a rerun into the
same folder (their resume), against one uninterrupted run: every output file must be byte-identical.

    kill_and_rerun.py AGGKIT --out DIR [--seed S] [--kills K] [--only scan|sweep|validate] [--jobs J]

For each command on its small scene (1-3 s): one uninterrupted run, then K times a run killed with SIGKILL
(of the command's process, as `kill -9 PID` does; `aggkit validate` arranges for its running scenes to end
with it) at a moment drawn uniformly in (2 %, 98 %) of the uninterrupted run's wall time (random.Random(seed):
the same moments on every run of the test, though where a run stands at a given moment depends on the load),
followed by a rerun that must exit as the uninterrupted run did. Every run writes into the same folder (so the
paths it records are the same) and is moved aside after. Then the two folders must hold the same files (a
left-over *.partial, a missing file, an extra one are all differences) with the same bytes.

Only what a run records about itself rather than about the physics may differ, and only in those fields:
wall times and rates per wall second (any JSON key ending in wall_seconds or _per_second: summary.json,
final.json, finished/*.json, validation.json), validate's --jobs (validation.json "jobs", report.html), the seconds and MPI rank of each scan or sweep run (timing.csv,
the `seconds,rank` columns of a scan's points/*.csv, a sweep point's "seconds"/"rank"), whether a scene was
finished in an earlier run (validation.json "resumed", report.html), and the wall-time cells of report.html and
of each scene's log. Those fields are blanked in both folders before the byte comparison (normalise() below);
everything else is compared as written.

With --jobs J (default 1) the killed validations and their reruns run `aggkit validate --jobs J`, against the
uninterrupted `--jobs 1`: with J > 1 its scan scene runs first as J MPI ranks (mpiexec), and a kill lands in
the middle of that MPI job too.

Exit 0: every rerun identical; 1: a difference (each differing file named, with its first differing line);
2: the harness itself failed (a reference run that did not succeed).
"""
import argparse
import json
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

# 8 points of ~0.2 s (N = 256, cutoff, t = 200, with the linear stability of each steady state): a kill
# lands before, between and inside point runs and the writing of the outputs.
SCAN_SCENE = """name = "kill-scan"
[model]
kernel = { name = "brownian", a = 0.9 }
size = 256
truncation = "cutoff"
[time]
end = 200.0
every = 1.0
[scan]
a = { from = 0.6, to = 0.9, count = 2 }
lambda = { from = 0.01, to = 1.0, count = 4, spacing = "log" }
"""

# DEM spheres in a periodic box, 2 restitutions x 3 realizations with their own random starts (a resumed
# run must redraw exactly the same start), plus a kinetic engine key: 6 runs of ~0.3-1 s.
SWEEP_SCENE = """name = "kill-sweep"
[particles]
dimension = 3
count = 60
radius = 1.0
mass = 1.0
boundary = "periodic"
volume_fraction = 0.1
initial = { cloud = "cube", speed = 1.0 }
seed = 3
[time]
end = 4.0
[[engine]]
name = "dem"
restitution = 0.5
contact_time = 0.05
[observe]
series = ["kinetic_energy"]
final = ["kinetic_energy", "clusters"]
[sweep]
"engine.restitution" = [0.3, 0.9]
realizations = 3
"""

# A run scene with a check (CVODE against the exact constant-kernel solution [Leyvraz2003]), a DSMC scene
# (random, seeded), a tiny scan scene: three scenes of ~0.2-2 s, run one at a time.
VALIDATE_SCENES = {
    "a-constant.toml": """name = "kill-constant"
[model]
kernel = { name = "constant" }
size = 2048
truncation = "drop"
[time]
end = 10.0
outputs = [0.5, 1.0, 5.0, 10.0]
[[engine]]
name = "cvode"
rtol = 1e-10
atol = 1e-14
[[engine]]
name = "exact"
[observe]
series = ["M0", "M2"]
[compare]
reference = "exact"
tolerance = { M0 = 1e-6, M2 = 1e-6 }
""",
    "b-dsmc.toml": """name = "kill-dsmc"
[model]
kernel = { name = "constant" }
size = 4096
truncation = "drop"
[time]
end = 5.0
outputs = [1.0, 2.0, 5.0]
[[engine]]
name = "dsmc"
particles = 200000
seed = 7
[[engine]]
name = "exact"
[observe]
series = ["M0"]
[compare]
reference = "exact"
tolerance = { M0 = 0.02 }
""",
    "c-scan.toml": SCAN_SCENE.replace('"kill-scan"', '"kill-validate-scan"').replace("count = 4", "count = 2")
                             .replace("size = 256", "size = 128"),
}

NUMBER = r"-?[0-9][0-9.eE+-]*"


def blank_run_fields(value, keys):
    """The JSON value with every entry named in `keys`, or a wall time or a rate per wall second, blanked."""
    if isinstance(value, dict):
        return {k: "*" if run_field(k, keys) else blank_run_fields(v, keys) for k, v in value.items()}
    if isinstance(value, list):
        return [blank_run_fields(v, keys) for v in value]
    return value


def run_field(key, keys):
    return key in keys or key.endswith("wall_seconds") or key.endswith("_per_second")


def normalise(relative, data):
    """The file's bytes with the fields that describe the run itself (not the physics) blanked."""
    name = relative.as_posix()
    if name.endswith(".json"):
        # summary.json, final.json, finished/*.json: the run's wall time; points/*.json of a sweep also its
        # seconds and rank; validation.json whether a scene was resumed (and how many were).
        keys = {"seconds", "rank"} if "points/" in name else set()
        if name == "validation.json":
            keys = {"resumed", "jobs"}  # --jobs: how it was run (the same outputs on any count)
        return json.dumps(blank_run_fields(json.loads(data), keys), sort_keys=True, indent=1).encode()
    if name.endswith("timing.csv"):
        # point/realization columns are the results' identity; seconds and rank are the run's.
        lines = data.decode().splitlines()
        header = lines[0].split(",") if lines else []
        drop = {i for i, c in enumerate(header) if c in ("seconds", "rank")}
        return "\n".join(",".join("*" if i in drop else f for i, f in enumerate(l.split(","))) for l in lines).encode()
    if "points/" in name and name.endswith(".csv"):
        # scan point files end in `,seconds,rank` (validation/scan/scan_record.hpp)
        lines = data.decode().splitlines()
        if lines and lines[0].endswith(",seconds,rank"):
            return "\n".join(l.rsplit(",", 2)[0] + ",*,*" for l in lines).encode()
        return data
    if name == "report.html":
        text = data.decode()
        text = text.replace(" (finished in an earlier run)", "")
        text = re.sub(r"wall time " + NUMBER + " s", "wall time * s", text)
        text = re.sub(r" · [0-9]+ jobs? · ", " · * jobs · ", text)
        # the scene's wall time, the cell before its verdict; an engine's, the cell after its status
        text = re.sub(r'<td class="num">' + NUMBER + r'( \(earlier run\))?</td>(?=<td class="(?!num))',
                      '<td class="num">*</td>', text)
        text = re.sub(r'(<td>[a-z ()]+</td><td class="num">)' + NUMBER + "</td>", r"\1*</td>", text)
        return text.encode()
    if name.startswith("logs/"):
        # a scene's own log: its engine table's "wall [s]" column (the third field of each row)
        out, in_table = [], False
        for line in data.decode().splitlines():
            if "wall [s]" in line:
                in_table = True
            elif in_table and line.strip():
                fields = line.split()
                if len(fields) > 2:
                    line = line.replace(fields[2], "*", 1) if fields[2] not in fields[:2] else line
            else:
                in_table = False
            out.append(line)
        return "\n".join(out).encode()
    return data


def tree(folder):
    return {p.relative_to(folder): p for p in sorted(folder.rglob("*")) if p.is_file()}


def first_difference(a, b):
    la, lb = a.decode(errors="replace").splitlines(), b.decode(errors="replace").splitlines()
    for i, (x, y) in enumerate(zip(la, lb)):
        if x != y:
            return f"line {i + 1}: {x[:160]!r} vs {y[:160]!r}"
    return f"{len(la)} vs {len(lb)} lines"


def compare(reference, rerun):
    """Names of differing files, each with why."""
    a, b = tree(reference), tree(rerun)
    problems = [f"{p}: only in the uninterrupted run" for p in sorted(set(a) - set(b))]
    problems += [f"{p}: only after kill and rerun" for p in sorted(set(b) - set(a))]
    for p in sorted(set(a) & set(b)):
        x, y = normalise(p, a[p].read_bytes()), normalise(p, b[p].read_bytes())
        if x != y:
            problems.append(f"{p}: differs, {first_difference(x, y)}")
    return problems


def command_line(aggkit, command, target, out, jobs=1):
    line = [aggkit, command, str(target), "--out", str(out), "--no-plot"]
    if command == "validate":
        line = [aggkit, "validate", "--jobs", str(jobs), "--out", str(out), "--no-plot"] + [str(t) for t in target]
    return line


def run(line, log):
    with open(log, "ab") as sink:
        return subprocess.run(line, stdout=sink, stderr=sink, timeout=600).returncode


def killed_run(line, log, moment):
    """Starts the command, kill -9 of its process (not of a group: its children get what the program
    arranges for them) after `moment` seconds; True if the kill landed before the command ended."""
    with open(log, "ab") as sink:
        process = subprocess.Popen(line, stdout=sink, stderr=sink)
        try:
            process.wait(timeout=moment)
            return False
        except subprocess.TimeoutExpired:
            os.kill(process.pid, signal.SIGKILL)
            process.wait()
            return True


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("aggkit")
    parser.add_argument("--out", required=True, type=Path)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--kills", type=int, default=3)
    parser.add_argument("--only", choices=["scan", "sweep", "validate"], action="append")
    parser.add_argument("--jobs", type=int, default=1, help="--jobs of the killed validations and their reruns")
    args = parser.parse_args()
    shutil.rmtree(args.out, ignore_errors=True)
    scenes = args.out / "scenes"
    scenes.mkdir(parents=True)
    (scenes / "scan.toml").write_text(SCAN_SCENE)
    (scenes / "sweep.toml").write_text(SWEEP_SCENE)
    for name, text in VALIDATE_SCENES.items():
        (scenes / "validate").mkdir(exist_ok=True)
        (scenes / "validate" / name).write_text(text)
    targets = {"scan": scenes / "scan.toml", "sweep": scenes / "sweep.toml",
               "validate": sorted((scenes / "validate").glob("*.toml"))}
    rng = random.Random(args.seed)
    failures = 0
    for command in args.only or ["scan", "sweep", "validate"]:
        base = args.out / command
        base.mkdir()
        log = base / "log.txt"
        started = time.monotonic()
        # Every run writes into the same folder (paths it records are then the same), moved aside after.
        work = base / "out"
        line = command_line(args.aggkit, command, targets[command], work)
        expected = run(line, log)
        wall = time.monotonic() - started
        work.rename(base / "reference")
        if expected not in (0, 1):
            print(f"kill_and_rerun: {command}: the uninterrupted run exited {expected} (log {log})")
            return 2
        line = command_line(args.aggkit, command, targets[command], work, args.jobs)
        for k in range(args.kills):
            moment = rng.uniform(0.02, 0.98) * wall
            landed = killed_run(line, log, moment)
            code = run(line, log)
            out = base / f"kill{k}"
            work.rename(out)
            problems = compare(base / "reference", out)
            if code != expected:
                problems.insert(0, f"the rerun exited {code}, the uninterrupted run {expected}")
            what = f"killed at {moment:.2f} s of {wall:.2f} s" if landed else f"ended before {moment:.2f} s"
            if problems:
                failures += 1
                print(f"kill_and_rerun: {command}: {what}, rerun: {len(problems)} difference(s):")
                for p in problems:
                    print(f"  {p}")
            else:
                print(f"kill_and_rerun: {command}: {what}, rerun: {len(tree(out))} files identical")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
