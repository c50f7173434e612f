#!/usr/bin/env bash
# Slurm batch script for one ensemble. Copy it, set the resources below, then
#
#   sbatch slurm_ensemble.sh JOB.toml [OUT.h5]
#
# from the directory where OUT should go (paths are taken from there). The
# arguments reach the script whatever the cluster's export rules
# (SBATCH_EXPORT=NONE included). Instead of arguments, the environment works
# too: sbatch --export=ALL,JOB=...,OUT=... slurm_ensemble.sh
#
# Settings (arguments, else the environment, else these defaults):
#   JOB       the job file (required)
#   OUT       the ensemble file; default JOBNAME_ensemble.h5 in the submit
#             directory. Resubmitting with the same OUT resumes the run, so
#             give two different ensembles two different OUTs.
#   TREEDYN   treedyn-ensemble; default: on PATH, else build/mpi/ under the
#             submit directory. Set it to YOUR build's absolute path, e.g.
#             TREEDYN=$HOME/treedyn/build/mpi/treedyn-ensemble
#   LAUNCH    srun (default: srun --mpi=pmix, Open MPI with PMIx as Debian's)
#             or mpirun (mpirun inside the allocation; MPIRUN_FLAGS added)
#   CHECKPOINT_EVERY  seconds between each rank's periodic checkpoints (300)
#
# What happens when the job is stopped:
# * Time limit: Slurm sends SIGUSR1 to this script about 120 s before the
#   limit (--signal=B:USR1@120; Slurm may send it up to 60 s earlier). The
#   ranks finish their sample in flight, save their checkpoint and exit 5;
#   the script requeues the job (--requeue) and the requeued job, same id,
#   resumes from the checkpoint. Slurm holds a requeued job for a while
#   (BeginTime, about 2 minutes) before it can start again.
# * `scancel` (SIGTERM to the ranks): the ranks save and exit 5 as above, but
#   a cancelled job is not requeued: submit the same command again (same
#   OUT), and it resumes. `scancel -s KILL` or a node failure leaves only the
#   last periodic checkpoint (at most CHECKPOINT_EVERY s old): the same
#   resubmission resumes from it.
#SBATCH --job-name=treedyn-ensemble
#SBATCH --ntasks=32
#SBATCH --cpus-per-task=1
#SBATCH --time=02:00:00
#SBATCH --output=treedyn-ensemble-%j.out
#SBATCH --error=treedyn-ensemble-%j.err
#SBATCH --open-mode=append
#SBATCH --signal=B:USR1@120
#SBATCH --requeue
set -euo pipefail

cd "${SLURM_SUBMIT_DIR:-$PWD}"
JOB=${1:-${JOB:-}}
OUT=${2:-${OUT:-}}
[ -n "$JOB" ] || { echo "usage: sbatch slurm_ensemble.sh JOB.toml [OUT.h5] (or JOB=... in the environment)" >&2; exit 2; }
[ -f "$JOB" ] || { echo "JOB: no such file: $JOB (relative paths start at $PWD)" >&2; exit 2; }
if [ -z "${TREEDYN:-}" ]; then
  TREEDYN=$(command -v treedyn-ensemble || echo build/mpi/treedyn-ensemble)
fi
[ -x "$TREEDYN" ] || { echo "TREEDYN: no executable $TREEDYN; set TREEDYN to your build's treedyn-ensemble (absolute path)" >&2; exit 2; }
# Absolute paths: a requeued job may start in another directory.
TREEDYN=$(realpath "$TREEDYN")
JOB=$(realpath "$JOB")
OUT=$(realpath -m "${OUT:-$(basename "${JOB%.toml}")_ensemble.h5}")
LAUNCH=${LAUNCH:-srun}
CHECKPOINT_EVERY=${CHECKPOINT_EVERY:-300}

case "$LAUNCH" in
  srun) launcher=(srun --mpi=pmix) ;;
  mpirun) launcher=(mpirun ${MPIRUN_FLAGS:-} -np "${SLURM_NTASKS:-1}") ;;
  *) echo "LAUNCH must be srun or mpirun, not '$LAUNCH'" >&2; exit 2 ;;
esac
echo "$(date -u +%FT%TZ) job ${SLURM_JOB_ID:-local} (restart ${SLURM_RESTART_COUNT:-0}): $JOB -> $OUT" >&2

# --resume starts from the beginning when there is no checkpoint yet.
"${launcher[@]}" "$TREEDYN" "$JOB" -o "$OUT" --resume --checkpoint-every "$CHECKPOINT_EVERY" \
  --progress-interval 60 &
ranks=$!
trapped=0
trap 'trapped=1; echo "$(date -u +%FT%TZ) time limit near (SIGUSR1): stopping the ranks" >&2; kill -USR1 "$ranks" 2>/dev/null || true' USR1
# A trap interrupts `wait` (status > 128); wait again for the ranks' own status
# (bash keeps it even when they have already ended).
while :; do
  status=0
  wait "$ranks" || status=$?
  [ "$trapped" = 1 ] || break
  trapped=0
done

if [ "$status" -eq 5 ] && [ -n "${SLURM_JOB_ID:-}" ]; then
  echo "$(date -u +%FT%TZ) interrupted: requeueing job $SLURM_JOB_ID to resume from $OUT.checkpoint" >&2
  scontrol requeue "$SLURM_JOB_ID"
fi
exit "$status"
