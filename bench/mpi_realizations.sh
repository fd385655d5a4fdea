#!/usr/bin/env bash
# Realizations over MPI ranks: the wall time of `aggkit run` on one scene of 8 realizations (one thread per
# rank) with one process and under `mpirun -np 2`, interleaved REPEATS times so that both see the same load,
# and a check that both wrote the same series.csv and final.json (but for wall_seconds).
#   bench/mpi_realizations.sh [REPEATS] [AGGKIT]     (default 3, build/aggkit)
# Prints one line per run (wall and CPU seconds) and the ratio of the median wall times (one process / two
# ranks). On a shared machine the ratio says how much of a second core the job got, not what MPI can give.
set -euo pipefail
cd "$(dirname "$0")/.."
repeats=${1:-3}
aggkit=${2:-build/aggkit}
scene=bench/scenes/mpi-realizations-ed.toml
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
mpirun=(mpirun --allow-run-as-root --oversubscribe -np 2)

seconds() {  # "wall cpu": wall seconds of the command and the CPU seconds (user + system) of it and its children
  /usr/bin/time -f '%e %U %S' -o "$out/time.txt" "$@" >/dev/null 2>&1
  awk '{printf "%s %.2f", $1, $2 + $3}' "$out/time.txt"
}

one=() two=()
for ((i = 1; i <= repeats; i++)); do
  read -r t1 c1 <<<"$(seconds "$aggkit" run "$scene" --out "$out/one" --no-plot --quiet)"
  read -r t2 c2 <<<"$(seconds "${mpirun[@]}" "$aggkit" run "$scene" --out "$out/two" --no-plot --quiet)"
  printf 'run %d: one process %.2f s (CPU %.2f s), mpirun -np 2 %.2f s (CPU %.2f s)\n' "$i" "$t1" "$c1" "$t2" "$c2"
  one+=("$t1") two+=("$t2")
  cmp -s "$out/one/ed/series.csv" "$out/two/ed/series.csv" || { echo "series.csv differ"; exit 1; }
  diff -q <(grep -v wall_seconds "$out/one/ed/final.json") <(grep -v wall_seconds "$out/two/ed/final.json") >/dev/null ||
    { echo "final.json differ"; exit 1; }
done
median() { printf '%s\n' "$@" | sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
m1=$(median "${one[@]}") m2=$(median "${two[@]}")
printf 'median: one process %.2f s, mpirun -np 2 %.2f s, ratio %.2f (outputs identical); load %s\n' "$m1" "$m2" \
  "$(echo "$m1 / $m2" | bc -l)" "$(cut -d' ' -f1-3 /proc/loadavg)"
