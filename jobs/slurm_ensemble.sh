#!/usr/bin/env bash
# Slurm batch script for one ensemble. Copy it, set the resources below, then
#
#   sbatch slurm_ensemble.sh JOB.toml [OUT.h5] [NAME=VALUE ...]
#
# from the directory where OUT should go (paths are taken from there), e.g.
#
#   sbatch slurm_ensemble.sh kapitza.toml TREEDYN=$HOME/treedyn/build/mpi/treedyn-ensemble
#
# Settings are NAME=VALUE arguments, else the environment, else the defaults
# below. Arguments reach the script whatever the cluster's export rules
# (SBATCH_EXPORT=NONE included), and a requeued job gets them again; the
# environment (TREEDYN=... sbatch ..., sbatch --export=ALL,JOB=...) does not
# reach the job where the cluster exports nothing.
#   JOB       the job file (required; also the first argument)
#   OUT       the ensemble file (also the second argument); default
#             JOBNAME_ensemble.h5 in the submit directory. Resubmitting with
#             the same OUT resumes the run, so give two ensembles two OUTs.
#   TREEDYN   treedyn-ensemble; default: on PATH, else build/mpi/ under the
#             submit directory. Give YOUR build's absolute path.
#   LAUNCH    srun (default: srun --mpi=pmix, Open MPI with PMIx as Debian's)
#             or mpirun (mpirun inside the allocation)
#   MPIRUN_FLAGS      words added after mpirun (LAUNCH=mpirun)
#   CHECKPOINT_EVERY  seconds between each rank's periodic checkpoints (300)
#
# How the job ends (the script's exit code):
# * 0: the ensemble is complete in OUT.
# * 5: stopped cleanly; every finished sample is in OUT.checkpoint/ and the
#   same submission resumes. At the time limit Slurm sends this script
#   SIGUSR1 120 s before it (--signal=B:USR1@120; up to 60 s earlier); the
#   script passes it on, the ranks save and exit 5, and the script requeues
#   the job (--requeue, same id), which resumes once Slurm lets it start
#   (2.25-3 minutes later on the cluster of issue 41). sacct shows each such
#   cycle as FAILED with ExitCode 5:0: interrupted and requeued, not failed.
#   scancel (SIGTERM to the script, the launcher and the ranks) also gives 5,
#   but a cancelled job is not requeued: submit the same command again.
#   With LAUNCH=mpirun, an mpirun that was signalled itself ends the job and
#   exits 1 (Open MPI's own code for that); the script then exits 5 when rank
#   0 reported a clean stop, "interrupted by SIG... after K of N samples;
#   resume with --resume" on stderr or in OUT.checkpoint/stopped (written
#   during this run), and keeps mpirun's code otherwise. (In an allocation,
#   Open MPI 4.1's mpirun drops that line once it is signalled.)
# * 2: the script refused its settings; other codes: treedyn-ensemble's (see
#   docs/commands.md, "Exit codes"), or the launcher's own. scancel -s KILL or a node failure
#   leave the last periodic checkpoint (at most CHECKPOINT_EVERY s old): the
#   same submission resumes from it.
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

usage="usage: sbatch slurm_ensemble.sh JOB.toml [OUT.h5] [NAME=VALUE ...] (NAME: JOB OUT TREEDYN LAUNCH MPIRUN_FLAGS CHECKPOINT_EVERY)"
stamp() { date -u +%FT%TZ; }
fail() { echo "$(stamp) error: $*" >&2; exit 2; }

# NAME=VALUE arguments override the environment; other arguments are JOB, OUT.
positional=()
for arg in "$@"; do
  if [[ $arg =~ ^([A-Z_]+)=(.*)$ ]]; then
    case ${BASH_REMATCH[1]} in
      JOB | OUT | TREEDYN | LAUNCH | MPIRUN_FLAGS | CHECKPOINT_EVERY) printf -v "${BASH_REMATCH[1]}" '%s' "${BASH_REMATCH[2]}" ;;
      *) fail "unknown setting ${BASH_REMATCH[1]}; $usage" ;;
    esac
  else
    positional+=("$arg")
  fi
done
[ "${#positional[@]}" -le 2 ] || fail "too many arguments: ${positional[*]}; $usage"
JOB=${positional[0]:-${JOB:-}}
OUT=${positional[1]:-${OUT:-}}

cd "${SLURM_SUBMIT_DIR:-$PWD}"
[ -n "$JOB" ] || fail "no job file; $usage"
[ -f "$JOB" ] || fail "JOB: no such file: $JOB (relative paths start at $PWD)"
if [ -z "${TREEDYN:-}" ]; then
  TREEDYN=$(command -v treedyn-ensemble || echo build/mpi/treedyn-ensemble)
fi
[ -x "$TREEDYN" ] || fail "TREEDYN: no executable $TREEDYN; give TREEDYN=/absolute/path/to/treedyn-ensemble as an argument"
# Absolute paths: a requeued job may start in another directory.
TREEDYN=$(realpath "$TREEDYN")
JOB=$(realpath "$JOB")
OUT=$(realpath -m "${OUT:-$(basename "${JOB%.toml}")_ensemble.h5}")
LAUNCH=${LAUNCH:-srun}
CHECKPOINT_EVERY=${CHECKPOINT_EVERY:-300}
[[ $CHECKPOINT_EVERY =~ ^[0-9]+([.][0-9]+)?$ ]] || fail "CHECKPOINT_EVERY must be a number of seconds, not '$CHECKPOINT_EVERY'"

case "$LAUNCH" in
  srun) launcher=(srun --mpi=pmix) ;;
  mpirun)
    read -r -a mpirun_flags <<< "${MPIRUN_FLAGS:-}"
    launcher=(mpirun "${mpirun_flags[@]}" -np "${SLURM_NTASKS:-1}")
    ;;
  *) fail "LAUNCH must be srun or mpirun, not '$LAUNCH'" ;;
esac
echo "$(stamp) job ${SLURM_JOB_ID:-local} (restart ${SLURM_RESTART_COUNT:-0}): $JOB -> $OUT" >&2

# The first stop signal is passed on to the launcher as SIGUSR1, which srun
# and mpirun both hand to the ranks without ending the job (a second one to
# the ranks more than 2 s after the first would end them at once, so later
# ones are only logged). SIGUSR1: the time limit is near, requeue. SIGTERM,
# SIGINT, SIGHUP: scancel, preemption or Ctrl-C, no requeue. Slurm signals
# the launcher and the ranks themselves as well; they take one stop once.
stop=
cancelled=
trapped=
ranks=
# shellcheck disable=SC2317  # called by the traps below
stop_on() {
  trapped=1
  case $1 in TERM | INT | HUP) cancelled=$1 ;; esac
  if [ -z "$stop" ]; then
    stop=$1
    echo "$(stamp) SIG$1: stopping the ranks" >&2
    [ -z "$ranks" ] || kill -USR1 "$ranks" 2>/dev/null || true
  else
    echo "$(stamp) SIG$1 while stopping (on SIG$stop): waiting for the ranks" >&2
  fi
}

# A copy of the launcher's stderr, for rank 0's "interrupted by ..." line,
# through a tee that ignores the stop signals (Slurm signals every process of
# the job; a dead tee would lose the line and break the launcher's stderr).
scratch=$(mktemp -d "${TMPDIR:-/tmp}/treedyn-ensemble.XXXXXX")
trap 'rm -rf "$scratch"' EXIT
stderr_copy=$scratch/stderr
touch "$scratch/launched"
trap '' USR1 TERM INT HUP
exec 3> >(exec tee -a "$stderr_copy" >&2)
tee_pid=$!
trap 'stop_on USR1' USR1
trap 'stop_on TERM' TERM
trap 'stop_on INT' INT
trap 'stop_on HUP' HUP

# --resume starts from the beginning when there is no checkpoint yet.
"${launcher[@]}" "$TREEDYN" "$JOB" -o "$OUT" --resume --checkpoint-every "$CHECKPOINT_EVERY" \
  --progress-interval 60 2>&3 &
ranks=$!
exec 3>&-
[ -z "$stop" ] || kill -USR1 "$ranks" 2>/dev/null || true
# A trap interrupts `wait` (status 128 + signal): wait again for the
# launcher's own status, which bash keeps even when the launcher has ended
# (127: that wait had it already).
status=0
wait "$ranks" || status=$?
while [ -n "$trapped" ]; do
  trapped=
  again=0
  wait "$ranks" || again=$?
  [ "$again" -eq 127 ] || status=$again
done
# tee ends once every writer of the launcher's stderr has (at most 10 s).
for _ in $(seq 100); do kill -0 "$tee_pid" 2>/dev/null || break; sleep 0.1; done

# Rank 0's line on the launcher's stderr, or in CHECKPOINT/stopped if this
# run left one there (for a launcher that does not show what the ranks print
# once it ends the job itself).
clean_stop='^interrupted by SIG[A-Z0-9]+ after [0-9]+ of [0-9]+ samples; resume with --resume'
stopped_line=$(grep -E "$clean_stop" "$stderr_copy" | tail -n 1 || true)
if [ -z "$stopped_line" ] && [ "$OUT.checkpoint/stopped" -nt "$scratch/launched" ]; then
  stopped_line=$(grep -E "$clean_stop" "$OUT.checkpoint/stopped" | tail -n 1 || true)
fi
if [ "$status" -ne 0 ] && [ "$status" -ne 5 ] && [ -n "$stopped_line" ]; then
  echo "$(stamp) $LAUNCH exited $status after ending the job itself, but rank 0 reported a clean stop: exit 5" >&2
  status=5
fi
if [ "$status" -eq 5 ]; then
  if [ "$stop" = USR1 ] && [ -z "$cancelled" ] && [ -n "${SLURM_JOB_ID:-}" ]; then
    echo "$(stamp) interrupted: requeueing job $SLURM_JOB_ID to resume from $OUT.checkpoint" >&2
    scontrol requeue "$SLURM_JOB_ID" || echo "$(stamp) error: scontrol requeue $SLURM_JOB_ID failed: submit the same command again to resume" >&2
  else
    echo "$(stamp) interrupted${stop:+ (SIG${cancelled:-$stop})}: submit the same command again to resume from $OUT.checkpoint" >&2
  fi
fi
exit "$status"
