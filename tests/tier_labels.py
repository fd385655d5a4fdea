"""Every CTest test of the build carries exactly one tier label (tests/CMakeLists.txt): unit, physics, cli,
mpi, python or fuzz; every test has a time limit (TIMEOUT > 0), so that a hang fails; and every test that runs the Catch2 executable names one of its test cases (CMake splits
a name at ';' into tests that match nothing and pass without running anything). Reads
`ctest --show-only=json-v1` and the executable's list of test cases (runs no test).

  tier_labels.py CTEST BUILD_DIR
"""
import collections
import json
import subprocess
import sys

TIERS = {"unit", "physics", "cli", "mpi", "python", "fuzz"}

ctest, build = sys.argv[1], sys.argv[2]
listing = json.loads(subprocess.run([ctest, "--test-dir", build, "--show-only=json-v1"], check=True,
                                    capture_output=True, text=True).stdout)
count = collections.Counter()
wrong = []
for test in listing["tests"]:
    labels = set()
    for prop in test.get("properties", []):
        if prop["name"] == "LABELS":
            labels.update(prop["value"])
    timeouts = [prop["value"] for prop in test.get("properties", []) if prop["name"] == "TIMEOUT"]
    if not timeouts or not timeouts[0] > 0:
        wrong.append(f"{test['name']}: no time limit (TIMEOUT)")
    tiers = labels & TIERS
    if len(tiers) != 1:
        wrong.append(f"{test['name']}: not exactly one tier label: {sorted(labels) or 'no labels'}")
    count.update(tiers)
catch_names = {}
for test in listing["tests"]:
    command = test.get("command") or []
    if command and command[0].endswith("aggkit_tests"):
        catch_names.setdefault(command[0], []).append(test["name"])
for executable, names in catch_names.items():
    # Catch2 v2 exits with the number of test cases listed.
    cases = set(subprocess.run([executable, "--list-test-names-only"], check=False, capture_output=True,
                               text=True).stdout.splitlines())
    wrong += [f"{name}: not a test case of {executable} (';' in a name?)" for name in names if name not in cases]
print(f"{len(listing['tests'])} tests: " + ", ".join(f"{t} {count[t]}" for t in sorted(TIERS)))
for line in wrong:
    print(line)
if not listing["tests"]:
    print("no tests listed")
sys.exit(1 if wrong or not listing["tests"] else 0)
