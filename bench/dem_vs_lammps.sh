#!/usr/bin/env bash
# DEM contact throughput against LAMMPS side by side (the case of bench/dem_throughput.cpp: N spheres at
# volume fraction 0.3, periodic, Hooke + tangential history, dt = t_c/50, no gravity). Installs Debian's
# `lammps` if missing (this script only; never a dependency of aggkit). Runs ours (1 and 2 threads) and LAMMPS
# (1 thread) interleaved ROUNDS times on the same start and prints particle-steps/s of each and the ratios of
# the best runs (a shared machine: interleaving keeps the ratios fair; the absolute figures are not), by wall
# time and, for one thread, by CPU time (ours: clock(); LAMMPS: its loop time × its reported "% CPU use"),
# which a loaded machine distorts less.
#   bench/dem_vs_lammps.sh [BUILD_DIR] [N] [STEPS] [ROUNDS]      defaults: build 10000 2000 3
# The ratios and LAMMPS' rates are appended to FIGURES/dem_vs_lammps.csv for bench/check (bench/figures.hpp's
# columns; FIGURES = $AGGKIT_BENCH_FIGURES or BUILD_DIR/bench/figures); ours are recorded by the bench itself.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
N=${2:-10000}
STEPS=${3:-2000}
ROUNDS=${4:-3}
if ! command -v lmp >/dev/null; then
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq lammps >/dev/null
fi
cmake --build "$BUILD" --target bench_dem_throughput >/dev/null
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
"$BUILD/bench/bench_dem_throughput" lammps "$WORK" "$N" "$STEPS"
echo "# $(cat /proc/loadavg) (load average), $(nproc) cores; N $N, $STEPS steps, $ROUNDS rounds"
best_ours1=0; best_ours2=0; best_lammps=0; best_ours1_cpu=0; best_lammps_cpu=0
max() { awk -v a="$1" -v b="$2" 'BEGIN { print (a > b ? a : b) }'; }
for r in $(seq "$ROUNDS"); do
  line=$("$BUILD/bench/bench_dem_throughput" run "$N" "$STEPS" 1); echo "$line"
  best_ours1=$(max "$best_ours1" "$(echo "$line" | sed -E 's/.*particle_steps_per_s ([^ ]+).*/\1/')")
  cpu=$(echo "$line" | sed -E 's/.*cpu_s ([^ ]+).*/\1/')
  best_ours1_cpu=$(max "$best_ours1_cpu" "$(awk -v n="$N" -v s="$STEPS" -v t="$cpu" 'BEGIN { printf "%.4g", n * s / t }')")
  loop=$(cd "$WORK" && OMP_NUM_THREADS=1 lmp -in in.dem -log lammps.log -screen none >/dev/null && grep "^Loop time" lammps.log)
  share=$(grep "% CPU use" "$WORK/lammps.log" | awk '{print $1}' | tr -d '%')
  seconds=$(echo "$loop" | awk '{print $4}')
  rate=$(awk -v n="$N" -v s="$STEPS" -v t="$seconds" 'BEGIN { printf "%.4g", n * s / t }')
  cpu_rate=$(awk -v n="$N" -v s="$STEPS" -v t="$seconds" -v p="$share" 'BEGIN { printf "%.4g", n * s / (t * p / 100) }')
  echo "lammps N $N steps $STEPS threads 1 wall_s $seconds cpu_share ${share}% particle_steps_per_s $rate per_cpu_s $cpu_rate"
  best_lammps=$(max "$best_lammps" "$rate")
  best_lammps_cpu=$(max "$best_lammps_cpu" "$cpu_rate")
  line=$("$BUILD/bench/bench_dem_throughput" run "$N" "$STEPS" 2); echo "$line"
  best_ours2=$(max "$best_ours2" "$(echo "$line" | sed -E 's/.*particle_steps_per_s ([^ ]+).*/\1/')")
done
figures=${AGGKIT_BENCH_FIGURES:-$BUILD/bench/figures}
mkdir -p "$figures"
[ -f "$figures/dem_vs_lammps.csv" ] || echo "date,bench,case,figure,value,unit,command" > "$figures/dem_vs_lammps.csv"
awk -v o1="$best_ours1" -v o2="$best_ours2" -v l="$best_lammps" -v oc="$best_ours1_cpu" -v lc="$best_lammps_cpu" \
    -v date="$(date -u +%Y-%m-%dT%H:%M:%SZ)" -v c="N=$N steps=$STEPS" -v cmd="bench/dem_vs_lammps.sh $BUILD $N $STEPS $ROUNDS" 'BEGIN {
  row = date ",dem_vs_lammps," c ",%s,%.6g,%s," cmd "\n";
  printf row, "lammps_particle_steps_per_s", l, "1/s"; printf row, "lammps_particle_steps_per_cpu_s", lc, "1/s";
  printf row, "ratio_1_thread_wall", o1 / l, "1"; printf row, "ratio_1_thread_cpu", oc / lc, "1";
  printf row, "ratio_2_threads_wall", o2 / l, "1" }' >> "$figures/dem_vs_lammps.csv"
awk -v o1="$best_ours1" -v o2="$best_ours2" -v l="$best_lammps" -v oc="$best_ours1_cpu" -v lc="$best_lammps_cpu" 'BEGIN {
  printf "best particle-steps/s (wall): ours 1 thread %.3g, ours 2 threads %.3g, LAMMPS 1 thread %.3g\n", o1, o2, l;
  printf "best particle-steps per CPU-second, 1 thread: ours %.3g, LAMMPS %.3g\n", oc, lc;
  printf "ratio ours/LAMMPS: 1 thread %.2f by wall, %.2f by CPU time (target >= 1); 2 threads %.2f by wall (target >= 1.6)\n", o1 / l, oc / lc, o2 / l }'
