#!/usr/bin/env bash
# Slurm batch script for one ensemble. Copy it anywhere, set JOB, OUT and the
# resources, then:   sbatch slurm_ensemble.sh
#
# * Ranks: `srun --mpi=pmix` (Open MPI built with PMIx, as Debian's is), or
#   set LAUNCH=mpirun to start the ranks with mpirun inside the allocation.
#   treedyn-ensemble refuses to run when Slurm asked for several tasks but
#   MPI sees only one rank (a launch without PMI).
# * Time limit: Slurm sends SIGUSR1 to this script 120 s before the limit
#   (--signal=B:USR1@120). The script passes it to the ranks, which finish
#   the sample in flight, write their checkpoint and exit 5; the script then
#   requeues the job (--requeue), and the requeued job resumes from the
#   checkpoint (--resume). A job killed outright (node failure, scancel -s
#   KILL) resumes the same way from its last periodic checkpoint
#   (--checkpoint-every, 300 s by default).
# * The output is named with the job id (the same after a requeue).
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
# Absolute paths: the job may start in another directory after a requeue.
TREEDYN=$(realpath "${TREEDYN:-build/mpi/treedyn-ensemble}")
JOB=$(realpath "${JOB:-jobs/crane_payload.toml}")
OUT=$(realpath -m "${OUT:-$(basename "${JOB%.toml}")_ensemble_${SLURM_JOB_ID:-local}.h5}")
LAUNCH=${LAUNCH:-srun}

case "$LAUNCH" in
  srun) launcher=(srun --mpi=pmix) ;;
  mpirun) launcher=(mpirun ${MPIRUN_FLAGS:-} -np "${SLURM_NTASKS:-1}") ;;
  *) echo "LAUNCH must be srun or mpirun, not '$LAUNCH'" >&2; exit 2 ;;
esac

# --resume starts from the beginning when there is no checkpoint yet.
"${launcher[@]}" "$TREEDYN" "$JOB" -o "$OUT" --resume --checkpoint-every 300 --progress-interval 60 &
ranks=$!
trap 'echo "$(date -u +%FT%TZ) time limit near: stopping the ranks" >&2; kill -USR1 "$ranks" 2>/dev/null || true' USR1
# `wait` returns early when the trap runs; wait again for the real status.
status=0
wait "$ranks" || status=$?
while kill -0 "$ranks" 2>/dev/null; do
  status=0
  wait "$ranks" || status=$?
done

if [ "$status" -eq 5 ] && [ -n "${SLURM_JOB_ID:-}" ]; then
  echo "$(date -u +%FT%TZ) interrupted: requeueing job $SLURM_JOB_ID to resume from $OUT.checkpoint" >&2
  scontrol requeue "$SLURM_JOB_ID"
fi
exit "$status"
