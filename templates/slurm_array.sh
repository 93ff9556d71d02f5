#!/bin/bash
# A peenflow sweep as a Slurm job array: each array task runs one shard of the cases,
# then one dependent job merges the shards into sweep.h5.
#
#   sbatch --array=1-8 templates/slurm_array.sh examples/table1_sweep.toml /scratch/$USER/table1
#   # when the array has finished (or chained: see the bottom of this file):
#   peenflow merge /scratch/$USER/table1/shard-*  --out /scratch/$USER/table1/all
#
# The array size is the number of shards N; task K (1..N) runs shard K/N. Re-submitting
# the same array resumes: finished cases (recognised by the hash of their resolved
# scene) are skipped, so only the cases of failed or timed-out tasks run again.
#
#SBATCH --job-name=peenflow-sweep
#SBATCH --cpus-per-task=8
#SBATCH --time=02:00:00
#SBATCH --output=peenflow-%A_%a.log

set -euo pipefail
SWEEP=${1:?usage: sbatch --array=1-N slurm_array.sh SWEEP.toml OUTDIR}
OUT=${2:?usage: sbatch --array=1-N slurm_array.sh SWEEP.toml OUTDIR}
K=${SLURM_ARRAY_TASK_ID:?run as a job array: sbatch --array=1-N}
N=${SLURM_ARRAY_TASK_COUNT:?run as a job array: sbatch --array=1-N}
PEENFLOW=${PEENFLOW:-peenflow}

# One directory per shard, so tasks never write the same files; -j uses the task's cores.
"$PEENFLOW" sweep "$SWEEP" --shard "$K/$N" --out "$OUT/shard-$K" -j "${SLURM_CPUS_PER_TASK:-1}"

# To merge automatically, submit a dependent job once:
#   jid=$(sbatch --parsable --array=1-8 templates/slurm_array.sh SWEEP.toml OUT)
#   sbatch --dependency=afterok:$jid --wrap "peenflow merge OUT/shard-* --out OUT/all"
