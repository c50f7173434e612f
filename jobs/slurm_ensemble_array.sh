#!/usr/bin/env bash
# Slurm array job: one ensemble split into parts by sample index, each part
# an array task (its own allocation, queued independently), then one merge.
#
#   sbatch --array=0-7 slurm_ensemble_array.sh            # 8 parts
#   sbatch --dependency=afterok:<array job id> --wrap \
#     "build/mpi/treedyn-ensemble merge -o crane_payload_ensemble.h5 crane_parts/part_*.part"
#
# or submit both at once with MERGE=1 (this script submits the merge itself
# from task 0, depending on the whole array). Part k holds the sample indices
# [k S / P, (k + 1) S / P) of S samples in P = SLURM_ARRAY_TASK_COUNT parts;
# every part also runs the pilot samples, so that all parts share one
# calibration and the merge is exact: the merged file is bitwise one run.
# Each task checkpoints and resumes like slurm_ensemble.sh.
#SBATCH --job-name=treedyn-part
#SBATCH --ntasks=8
#SBATCH --cpus-per-task=1
#SBATCH --time=01:00:00
#SBATCH --output=treedyn-part-%A_%a.out
#SBATCH --error=treedyn-part-%A_%a.err
#SBATCH --open-mode=append
#SBATCH --signal=B:USR1@120
#SBATCH --requeue
set -euo pipefail

cd "${SLURM_SUBMIT_DIR:-$PWD}"
TREEDYN=$(realpath "${TREEDYN:-build/mpi/treedyn-ensemble}")
JOB=$(realpath "${JOB:-jobs/crane_payload.toml}")
PARTS=$(realpath -m "${PARTS:-$(basename "${JOB%.toml}")_parts}")
OUT=$(realpath -m "${OUT:-$(basename "${JOB%.toml}")_ensemble.h5}")
mkdir -p "$PARTS"

task=${SLURM_ARRAY_TASK_ID:?submit with sbatch --array=0-N}
count=${SLURM_ARRAY_TASK_COUNT:?submit with sbatch --array=0-N}
# The number of samples (saltelli: all N (D + 2) runs), from --check.
samples=$("$TREEDYN" "$JOB" --check | sed -n 's/^ensemble: \([0-9][0-9]*\) samples.*/\1/p')
[ -n "$samples" ] || { echo "could not read the number of samples from --check" >&2; exit 2; }
first=$(( task * samples / count ))
end=$(( (task + 1) * samples / count ))
part="$PARTS/part_$(printf '%04d' "$task").part"

if [ "$task" -eq 0 ] && [ "${MERGE:-0}" = 1 ] && [ "${SLURM_RESTART_COUNT:-0}" = 0 ]; then
  sbatch --dependency="afterok:${SLURM_ARRAY_JOB_ID}" --job-name=treedyn-merge --ntasks=1 \
    --output="treedyn-merge-${SLURM_ARRAY_JOB_ID}.out" \
    --wrap "$(printf '%q ' "$TREEDYN" merge -o "$OUT") $(printf '%q' "$PARTS")/part_*.part"
fi

srun --mpi=pmix "$TREEDYN" "$JOB" -o "$part" --samples "$first:$end" --resume --progress-interval 60 &
ranks=$!
trap 'kill -USR1 "$ranks" 2>/dev/null || true' USR1
status=0
wait "$ranks" || status=$?
while kill -0 "$ranks" 2>/dev/null; do
  status=0
  wait "$ranks" || status=$?
done
if [ "$status" -eq 5 ]; then
  scontrol requeue "${SLURM_ARRAY_JOB_ID}_${SLURM_ARRAY_TASK_ID}"
fi
exit "$status"
