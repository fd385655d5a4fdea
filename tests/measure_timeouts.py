"""Writes tests/test_timeouts.cmake: each Catch2 test case's CTest TIMEOUT from its measured time, so that a
hang fails instead of stalling the run (tests/CMakeLists.txt includes the file after the discovered tests).

  measure_timeouts.py BUILD_DIR [--factor 5] [--floor 30] [--keep-higher]

Reads the times of the last runs of the suite in BUILD_DIR (CTest's Testing/Temporary/CTestCostData.txt:
the mean wall time of each test over its runs) and the list of tests (`ctest --show-only=json-v1`); the
limit is max(floor, factor x measured), rounded up to a multiple of 10 s. A test case without a measured time
is left out (it gets its tier's limit). Prints each tier's slowest case, from which the tier limits in
tests/CMakeLists.txt are chosen. Measure on the machine the suite runs on, with the suite's parallelism
(ctest -j2 on 2 cores shared with other work gives times up to about twice those of an idle machine).
--keep-higher keeps a case's limit (and its measured time) from the file already there where it is larger: the
cost data are means over whatever runs the build folder saw, and a run of a few cases alone reads them faster
than the suite under load does.
"""
import argparse
import collections
import json
import math
import pathlib
import re
import subprocess

TIERS = ("unit", "physics", "cli", "mpi")

parser = argparse.ArgumentParser()
parser.add_argument("build")
parser.add_argument("--factor", type=float, default=5.0)
parser.add_argument("--floor", type=float, default=30.0)
parser.add_argument("--keep-higher", action="store_true")
args = parser.parse_args()
out = pathlib.Path(__file__).with_name("test_timeouts.cmake")
earlier = {}
if args.keep_higher and out.exists():
    for line in out.read_text().splitlines():
        match = re.match(r"aggkit_test_timeout\(\[==\[(.*)\]==\] (\d+)\)  # measured ([\d.]+) s", line)
        if match:
            earlier[match.group(1)] = (int(match.group(2)), float(match.group(3)))

build = pathlib.Path(args.build)
costs = {}
for line in (build / "Testing" / "Temporary" / "CTestCostData.txt").read_text().splitlines():
    if line.strip() == "---":
        break
    parts = line.rsplit(" ", 2)
    if len(parts) == 3:
        costs[parts[0]] = float(parts[2])
listing = json.loads(subprocess.run(["ctest", "--test-dir", str(build), "--show-only=json-v1"], check=True,
                                    capture_output=True, text=True).stdout)
rows = []
slowest = collections.defaultdict(float)
for test in listing["tests"]:
    command = test.get("command") or []
    if not command or not command[0].endswith("aggkit_tests") or test["name"] not in costs:
        continue
    labels = [v for p in test.get("properties", []) if p["name"] == "LABELS" for v in p["value"]]
    measured = costs[test["name"]]
    limit = max(args.floor, math.ceil(args.factor * measured / 10) * 10)
    if test["name"] in earlier and earlier[test["name"]][0] > limit:
        limit, measured = earlier[test["name"]]
    rows.append((test["name"], int(limit), measured))
    for tier in labels:
        if tier in TIERS:
            slowest[tier] = max(slowest[tier], measured)
if any("]==]" in name for name, _, _ in rows):
    raise SystemExit("a test name holds ]==]: choose another bracket level")
with open(out, "w") as f:
    f.write("# Each Catch2 test case's CTest TIMEOUT in seconds: max(%g, %g x its measured wall time), rounded up to\n"
            "# 10 s. Written by tests/measure_timeouts.py from a run of the whole suite (ctest -j2, 2 shared cores);\n"
            "# rerun it after adding slow tests. Cases not listed get their tier's limit (tests/CMakeLists.txt).\n"
            % (args.floor, args.factor))
    for name, limit, measured in sorted(rows):
        f.write("aggkit_test_timeout([==[%s]==] %d)  # measured %.1f s\n" % (name, limit, measured))
print(f"{out}: {len(rows)} test cases")
for tier in TIERS:
    print(f"  {tier}: slowest case {slowest[tier]:.1f} s")
