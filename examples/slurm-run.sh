#!/usr/bin/env bash
# A SLURM batch job that runs aggkit scenes on several nodes: `aggkit run` spreads the realizations of the
# particle engines (ED, TS, DEM) and the runs of DSMC over the MPI ranks, with each engine's `threads`
# within a rank; rank 0 writes the outputs, which are those of a one-process run with the same seeds.
# Submit from the aggkit checkout (its build/ and validation/ on a file system every node sees):
#   sbatch examples/slurm-run.sh validation/scenes/SCENE.toml results/SCENE
# Checkpoints need one process (`aggkit run --checkpoint-every` is refused under several ranks): a job that
# may hit its time limit is better run as several smaller scenes or as an `aggkit sweep`, which resumes.
#SBATCH --job-name=aggkit-run        # the name squeue shows
#SBATCH --nodes=2                    # machines
#SBATCH --ntasks-per-node=4          # MPI ranks per machine: 8 ranks in all
#SBATCH --cpus-per-task=2            # cores per rank, for the engine's `threads = 2` (not 0: every core of the node)
#SBATCH --time=02:00:00              # wall-time limit; the job is killed after it
#SBATCH --output=aggkit-%j.log       # stdout and stderr (progress lines come from rank 0 only)
set -euo pipefail                    # stop at the first failing command

scene=${1:?usage: sbatch examples/slurm-run.sh SCENE.toml OUT_DIR}   # the scene file to run
out=${2:?usage: sbatch examples/slurm-run.sh SCENE.toml OUT_DIR}     # its output folder (created if needed)
aggkit=${AGGKIT:-build/aggkit}       # the aggkit program (set AGGKIT for an installed one)

export OMP_NUM_THREADS=1             # no hidden threads from libraries beyond the engines' own

# One scene, its realizations over all 8 ranks. srun starts the ranks through SLURM's PMI (the same as
# `mpirun -np 8` in an allocation); --cpus-per-task keeps each rank's threads on their own cores.
srun --cpus-per-task="$SLURM_CPUS_PER_TASK" "$aggkit" run "$scene" --out "$out" --no-plot

# Validation scenes on a cluster: `aggkit validate` runs scenes as child processes on one node and refuses
# mpirun, so each scene runs alone over all ranks; each `aggkit run` exits 0 when its comparisons pass,
# 1 when one fails, 2 for bad input. Uncomment to run the listed shipped scenes one after another:
# for name in ballistic-ts-vs-ed dsmc-ballistic; do                               # shipped scene names (validation/scenes/)
#   srun "$aggkit" run "validation/scenes/$name.toml" --out "$out/validation/$name" --no-plot \
#     || echo "scene $name: exit status $?"                               # record a failure, go on with the next
# done

# All fast-tier validation scenes on this job's first node only (child processes, 8 at a time):
# srun --nodes=1 --ntasks=1 --cpus-per-task=8 "$aggkit" validate --jobs 8 --out "$out/validation"
