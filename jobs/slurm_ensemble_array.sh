#!/usr/bin/env bash
# Slurm array job: one ensemble split into parts by sample index, each part an
# array task (its own allocation, queued independently), then one merge:
#
#   MERGE=1 sbatch --array=0-7 slurm_ensemble_array.sh JOB.toml [OUT.h5]
#
# from the directory where OUT should go. Task 0 submits the merge itself, as a
# job that starts when the whole array has succeeded (afterok); it writes OUT
# and removes the parts (KEEP_PARTS=1 keeps them). Without MERGE=1, merge by
# hand once every task is done, listing exactly the parts of this array:
#
#   treedyn-ensemble merge -o OUT.h5 JOBNAME_parts/8/part_000{0..7}.part
#
# Part k of P = SLURM_ARRAY_TASK_COUNT holds the sample indices
# [k S / P, (k + 1) S / P) of S samples (saltelli: all N (D + 2) runs); every
# part also runs the pilot samples, so that all parts share one calibration and
# the merged file is bitwise one run. Parts go to PARTS/P/ (PARTS default
# JOBNAME_parts), so an earlier run with another task count never mixes in.
#
# Settings as in slurm_ensemble.sh (JOB, OUT, TREEDYN, LAUNCH,
# CHECKPOINT_EVERY), plus PARTS, MERGE and KEEP_PARTS. Each task checkpoints,
# stops at the time limit, requeues and resumes like slurm_ensemble.sh; a
# cancelled task resumes when the same array is submitted again.
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

task=${SLURM_ARRAY_TASK_ID:-}
count=${SLURM_ARRAY_TASK_COUNT:-}
[ -n "$task" ] && [ -n "$count" ] || { echo "submit with sbatch --array=0-N (N + 1 parts)" >&2; exit 2; }
if [ "${SLURM_ARRAY_TASK_MIN:-0}" != 0 ] || [ "${SLURM_ARRAY_TASK_MAX:-$((count - 1))}" != $((count - 1)) ]; then
  echo "the array must be 0-N with every index (got ${SLURM_ARRAY_TASK_MIN}-${SLURM_ARRAY_TASK_MAX}, $count tasks)" >&2
  exit 2
fi
cd "${SLURM_SUBMIT_DIR:-$PWD}"
JOB=${1:-${JOB:-}}
OUT=${2:-${OUT:-}}
[ -n "$JOB" ] || { echo "usage: sbatch --array=0-N slurm_ensemble_array.sh JOB.toml [OUT.h5]" >&2; exit 2; }
[ -f "$JOB" ] || { echo "JOB: no such file: $JOB (relative paths start at $PWD)" >&2; exit 2; }
if [ -z "${TREEDYN:-}" ]; then
  TREEDYN=$(command -v treedyn-ensemble || echo build/mpi/treedyn-ensemble)
fi
[ -x "$TREEDYN" ] || { echo "TREEDYN: no executable $TREEDYN; set TREEDYN to your build's treedyn-ensemble (absolute path)" >&2; exit 2; }
TREEDYN=$(realpath "$TREEDYN")
JOB=$(realpath "$JOB")
name=$(basename "${JOB%.toml}")
OUT=$(realpath -m "${OUT:-${name}_ensemble.h5}")
PARTS=$(realpath -m "${PARTS:-${name}_parts}")/$count
LAUNCH=${LAUNCH:-srun}
CHECKPOINT_EVERY=${CHECKPOINT_EVERY:-300}
case "$LAUNCH" in
  srun) launcher=(srun --mpi=pmix) ;;
  mpirun) launcher=(mpirun ${MPIRUN_FLAGS:-} -np "${SLURM_NTASKS:-1}") ;;
  *) echo "LAUNCH must be srun or mpirun, not '$LAUNCH'" >&2; exit 2 ;;
esac

# The number of samples (saltelli: all N (D + 2) runs), from --check.
samples=$("$TREEDYN" "$JOB" --check | sed -n 's/^ensemble: \([0-9][0-9]*\) samples.*/\1/p')
[ -n "$samples" ] || { echo "could not read the number of samples from $TREEDYN $JOB --check" >&2; exit 2; }
first=$(( task * samples / count ))
end=$(( (task + 1) * samples / count ))
mkdir -p "$PARTS"
part="$PARTS/part_$(printf '%04d' "$task").part"
echo "$(date -u +%FT%TZ) task $task of $count (restart ${SLURM_RESTART_COUNT:-0}): samples $first..$((end - 1)) -> $part" >&2

if [ "$task" -eq 0 ] && [ "${MERGE:-0}" = 1 ] && [ "${SLURM_RESTART_COUNT:-0}" = 0 ]; then
  list=()
  for ((k = 0; k < count; k++)); do list+=("$PARTS/part_$(printf '%04d' "$k").part"); done
  merge="$(printf '%q ' "$TREEDYN" merge -o "$OUT" "${list[@]}")"
  [ "${KEEP_PARTS:-0}" = 1 ] || merge+=" && rm -f $(printf '%q ' "${list[@]}")"
  sbatch --dependency="afterok:${SLURM_ARRAY_JOB_ID}" --job-name=treedyn-merge --ntasks=1 \
    --output="treedyn-merge-${SLURM_ARRAY_JOB_ID}.out" --wrap "$merge"
fi

"${launcher[@]}" "$TREEDYN" "$JOB" -o "$part" --samples "$first:$end" --resume \
  --checkpoint-every "$CHECKPOINT_EVERY" --progress-interval 60 &
ranks=$!
trapped=0
trap 'trapped=1; echo "$(date -u +%FT%TZ) time limit near (SIGUSR1): stopping task $task" >&2; kill -USR1 "$ranks" 2>/dev/null || true' USR1
# A trap interrupts `wait` (status > 128); wait again for the ranks' own status
# (bash keeps it even when they have already ended).
while :; do
  status=0
  wait "$ranks" || status=$?
  [ "$trapped" = 1 ] || break
  trapped=0
done
if [ "$status" -eq 5 ]; then
  echo "$(date -u +%FT%TZ) interrupted: requeueing task ${SLURM_ARRAY_JOB_ID}_${task} to resume" >&2
  scontrol requeue "${SLURM_ARRAY_JOB_ID}_${task}"
fi
exit "$status"
