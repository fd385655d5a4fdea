#!/usr/bin/env bash
# A longer run of the scene fuzzer (tests/fuzz/fuzz_scenes.py; the test suite runs it for 45 s as
# fuzz_scenes_quick): mutates the shipped scenes for BUDGET seconds, one aggkit run at a time, and prints
# the statistics and the findings. Results and the command that produced them: bench/results/log/scene-fuzzing.md,
# "Scene fuzzing".
#   bench/fuzz_scenes.sh [BUDGET_S [SEED]]     defaults 600 s, seed 7 (the quick test uses seed 1)
#   BUILD_DIR=dir OUT=dir bench/fuzz_scenes.sh  binary BUILD_DIR/aggkit (default build), output folder
#                                               OUT (default results/fuzz-scenes)
# Exit status: the fuzzer's, 0 without findings, 1 with (details in OUT/findings.json and OUT/finding-NN.toml).
set -uo pipefail
cd "$(dirname "$0")/.."
budget=${1:-600}
seed=${2:-7}
build=${BUILD_DIR:-build}
out=${OUT:-results/fuzz-scenes}
test -x "$build/aggkit" || { echo "fuzz_scenes.sh: no $build/aggkit; build first (scripts/setup)" >&2; exit 2; }
echo "fuzz_scenes.sh: load $(cut -d' ' -f1-3 /proc/loadavg), budget ${budget} s, seed ${seed}, output ${out}"
/usr/bin/python3 tests/fuzz/fuzz_scenes.py "$build/aggkit" --seed "$seed" --budget "$budget" --timeout 10 --out "$out"
status=$?
/usr/bin/python3 -c 'import json, sys; s = json.load(open(sys.argv[1])); print(json.dumps({k: s[k] for k in ("executions", "executions_per_s", "elapsed_s", "exit_codes", "findings", "finding_kinds", "mean_run_s_by_scene")}, indent=1))' "$out/stats.json"
# The figures for bench/check (bench/figures.hpp's columns), appended to FIGURES/fuzz_scenes.csv.
figures=${AGGKIT_BENCH_FIGURES:-$build/bench/figures}
mkdir -p "$figures"
/usr/bin/python3 - "$out/stats.json" "$figures/fuzz_scenes.csv" "bench/fuzz_scenes.sh $budget $seed" "seed=$seed budget=$budget" <<'PY'
import csv, datetime, json, os, sys
stats, path, command, case = json.load(open(sys.argv[1])), sys.argv[2], sys.argv[3], sys.argv[4]
date = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")
fresh = not os.path.exists(path)
with open(path, "a", newline="") as f:
    w = csv.writer(f, lineterminator="\n")
    if fresh:
        w.writerow(["date", "bench", "case", "figure", "value", "unit", "command"])
    w.writerow([date, "fuzz_scenes", case, "executions_per_second", stats["executions_per_s"], "1/s", command])
    w.writerow([date, "fuzz_scenes", case, "findings", stats["findings"], "1", command])
PY
exit $status
