#!/usr/bin/env bash
# Slurm array job: one ensemble split into parts by sample index, each part an
# array task (its own allocation, queued independently), then one merge:
#
#   sbatch --array=0-7 slurm_ensemble_array.sh JOB.toml [OUT.h5] MERGE=1 [NAME=VALUE ...]
#
# from the directory where OUT should go. With MERGE=1 task 0 queues the merge
# as a job that starts when the whole array has succeeded (afterok), in the
# array's partition, account and QOS and with its time limit (MERGE_PARTITION,
# MERGE_ACCOUNT, MERGE_QOS, MERGE_TIME replace them; '-' leaves one to the
# cluster's default). The merge writes OUT and removes the parts (KEEP_PARTS=1
# keeps them). Task 0 fails (exit 2, after running its part) when the merge
# could not be queued. Its id is kept in PARTS/P/merge.job: a new array over
# the same parts cancels an earlier array's merge left waiting forever
# (DependencyNeverSatisfied), or names it when it still waits on a live array.
# Without MERGE=1, merge by hand once every task is done (any number of parts;
# the names sort by index):
#
#   treedyn-ensemble merge -o OUT.h5 JOBNAME_parts/8/part_*.part
#
# Self-contained on purpose, like slurm_ensemble.sh, whose launch, signal
# and clean-stop code it repeats: sbatch runs a copy of a script from its
# spool directory, where no sibling file can be sourced, and users copy one
# script (tests/jobs/slurm_scripts_test.sh checks both the same way).
#
# Part k of P = SLURM_ARRAY_TASK_COUNT holds the sample indices
# [k S / P, (k + 1) S / P) of S samples (saltelli: all N (D + 2) runs); every
# part also runs the pilot samples, so that all parts share one calibration and
# the merged file is bitwise one run. Parts go to PARTS/P/ (PARTS default
# JOBNAME_parts), so an earlier run with another task count never mixes in.
#
# Settings are NAME=VALUE arguments, else the environment, else the defaults,
# as in slurm_ensemble.sh (JOB, OUT, TREEDYN, LAUNCH, MPIRUN_FLAGS,
# CHECKPOINT_EVERY), plus PARTS, MERGE, KEEP_PARTS and the MERGE_* above. Each
# task checkpoints, stops, requeues and resumes, and exits, like
# slurm_ensemble.sh; a cancelled task resumes when the same array is
# submitted again.
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

usage="usage: sbatch --array=0-N slurm_ensemble_array.sh JOB.toml [OUT.h5] [NAME=VALUE ...] (NAME: JOB OUT TREEDYN LAUNCH MPIRUN_FLAGS CHECKPOINT_EVERY PARTS MERGE KEEP_PARTS MERGE_PARTITION MERGE_ACCOUNT MERGE_QOS MERGE_TIME)"
stamp() { date -u +%FT%TZ; }
fail() { echo "$(stamp) error: $*" >&2; exit 2; }

# NAME=VALUE arguments override the environment; other arguments are JOB, OUT.
positional=()
for arg in "$@"; do
  if [[ $arg =~ ^([A-Z_]+)=(.*)$ ]]; then
    case ${BASH_REMATCH[1]} in
      JOB | OUT | TREEDYN | LAUNCH | MPIRUN_FLAGS | CHECKPOINT_EVERY | PARTS | MERGE | KEEP_PARTS | \
        MERGE_PARTITION | MERGE_ACCOUNT | MERGE_QOS | MERGE_TIME)
        printf -v "${BASH_REMATCH[1]}" '%s' "${BASH_REMATCH[2]}" ;;
      *) fail "unknown setting ${BASH_REMATCH[1]}; $usage" ;;
    esac
  else
    positional+=("$arg")
  fi
done
[ "${#positional[@]}" -le 2 ] || fail "too many arguments: ${positional[*]}; $usage"
JOB=${positional[0]:-${JOB:-}}
OUT=${positional[1]:-${OUT:-}}
MERGE=${MERGE:-0}
KEEP_PARTS=${KEEP_PARTS:-0}
[[ $MERGE =~ ^[01]$ ]] || fail "MERGE must be 0 or 1, not '$MERGE'"
[[ $KEEP_PARTS =~ ^[01]$ ]] || fail "KEEP_PARTS must be 0 or 1, not '$KEEP_PARTS'"

task=${SLURM_ARRAY_TASK_ID:-}
count=${SLURM_ARRAY_TASK_COUNT:-}
if [ -z "$task" ] || [ -z "$count" ] || [ -z "${SLURM_ARRAY_JOB_ID:-}" ]; then
  fail "submit with sbatch --array=0-N (N + 1 parts); $usage"
fi
if [ "${SLURM_ARRAY_TASK_MIN:-0}" != 0 ] || [ "${SLURM_ARRAY_TASK_MAX:-$((count - 1))}" != $((count - 1)) ]; then
  fail "the array must be 0-N with every index (got ${SLURM_ARRAY_TASK_MIN:-}-${SLURM_ARRAY_TASK_MAX:-}, $count tasks)"
fi
cd "${SLURM_SUBMIT_DIR:-$PWD}"
[ -n "$JOB" ] || fail "no job file; $usage"
[ -f "$JOB" ] || fail "JOB: no such file: $JOB (relative paths start at $PWD)"
if [ -z "${TREEDYN:-}" ]; then
  TREEDYN=$(command -v treedyn-ensemble || echo build/mpi/treedyn-ensemble)
fi
[ -x "$TREEDYN" ] || fail "TREEDYN: no executable $TREEDYN; give TREEDYN=/absolute/path/to/treedyn-ensemble as an argument"
TREEDYN=$(realpath "$TREEDYN")
JOB=$(realpath "$JOB")
name=$(basename "${JOB%.toml}")
OUT=$(realpath -m "${OUT:-${name}_ensemble.h5}")
parts_base=$(realpath -m "${PARTS:-${name}_parts}")
PARTS=$parts_base/$count
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

# The number of samples (saltelli: all N (D + 2) runs), from --check.
samples=$("$TREEDYN" "$JOB" --check | sed -n 's/^ensemble: \([0-9][0-9]*\) samples.*/\1/p')
[ -n "$samples" ] || fail "could not read the number of samples from $TREEDYN $JOB --check"
first=$((task * samples / count))
end=$(((task + 1) * samples / count))
mkdir -p "$PARTS"
part="$PARTS/part_$(printf '%04d' "$task").part"
echo "$(stamp) task $task of $count (restart ${SLURM_RESTART_COUNT:-0}): samples $first..$((end - 1)) -> $part" >&2
scratch=$(mktemp -d "${TMPDIR:-/tmp}/treedyn-part.XXXXXX")
trap 'rm -rf "$scratch"' EXIT

# An earlier array's merge job, recorded in PARTS/*/merge.job as "MERGE_ID
# ARRAY_ID": cancelled when it waits for a dependency that can no longer be
# met (that array was cancelled or failed), else named.
earlier_merges() {
  local record merge_id array_id state reason
  for record in "$parts_base"/*/merge.job; do
    [ -f "$record" ] || continue
    read -r merge_id array_id < "$record" || true
    if [ -z "${merge_id:-}" ] || [ "${array_id:-}" = "$SLURM_ARRAY_JOB_ID" ]; then continue; fi
    read -r state reason < <(squeue -h -j "$merge_id" -o '%T %r' 2>/dev/null || true) || true
    case ${state:-} in
      PENDING | RUNNING | CONFIGURING | SUSPENDED | REQUEUED | REQUEUE_HOLD) ;;
      *) rm -f "$record"; continue ;;  # no longer queued
    esac
    if [ "$state" = PENDING ] && [ "${reason:-}" = DependencyNeverSatisfied ]; then
      if scancel "$merge_id"; then
        echo "$(stamp) cancelled job $merge_id, the merge of the earlier array $array_id (DependencyNeverSatisfied)" >&2
        rm -f "$record"
      else
        echo "$(stamp) warning: job $merge_id, the merge of the earlier array $array_id, waits forever (DependencyNeverSatisfied): cancel it with scancel $merge_id" >&2
      fi
    else
      echo "$(stamp) warning: job $merge_id, the merge of the earlier array $array_id, is still queued ($state, ${reason:-}) and would merge $record's parts too: if that array is not meant to finish, scancel $merge_id" >&2
    fi
  done
}

# The merge job, queued by task 0 once per array (a requeued task 0 finds it
# in PARTS/merge.job); with the running task's partition, account, QOS and
# time limit unless the MERGE_* settings say otherwise.
merge_error=
queue_merge() {
  local record="$PARTS/merge.job" merge_id array_id list k merge flags value reply
  if [ -f "$record" ]; then
    read -r merge_id array_id < "$record" || true
    if [ "${array_id:-}" = "$SLURM_ARRAY_JOB_ID" ]; then
      echo "$(stamp) the merge is job $merge_id (queued before this task was requeued)" >&2
      return 0
    fi
  fi
  list=()
  for ((k = 0; k < count; k++)); do list+=("$PARTS/part_$(printf '%04d' "$k").part"); done
  merge="$(printf '%q ' "$TREEDYN" merge -o "$OUT" "${list[@]}")"
  [ "$KEEP_PARTS" = 1 ] || merge+=" && rm -f $(printf '%q ' "${list[@]}")"
  merge+=" && rm -f $(printf '%q' "$record")"
  flags=(--parsable --dependency="afterok:${SLURM_ARRAY_JOB_ID}" --job-name=treedyn-merge --ntasks=1
    --output="treedyn-merge-${SLURM_ARRAY_JOB_ID}.out")
  value=${MERGE_PARTITION:-${SLURM_JOB_PARTITION:-}}
  [ -z "$value" ] || [ "$value" = - ] || flags+=(--partition="$value")
  value=${MERGE_ACCOUNT:-${SLURM_JOB_ACCOUNT:-}}
  [ -z "$value" ] || [ "$value" = - ] || flags+=(--account="$value")
  value=${MERGE_QOS:-${SLURM_JOB_QOS:-}}
  [ -z "$value" ] || [ "$value" = - ] || flags+=(--qos="$value")
  value=${MERGE_TIME:-}
  [ -n "$value" ] || value=$(squeue -h -j "${SLURM_JOB_ID:-$SLURM_ARRAY_JOB_ID}" -o %l 2>/dev/null || true)
  case $value in '' | - | UNLIMITED | NOT_SET | INVALID) ;; *) flags+=(--time="$value") ;; esac
  if reply=$(sbatch "${flags[@]}" --wrap "$merge" 2> "$scratch/sbatch") &&
    merge_id=$(tail -n 1 <<< "$reply") && merge_id=${merge_id%%;*} && [[ $merge_id =~ ^[0-9]+$ ]]; then
    echo "$merge_id $SLURM_ARRAY_JOB_ID" > "$record"
    echo "$(stamp) merge queued: job $merge_id writes $OUT once every task of array $SLURM_ARRAY_JOB_ID has succeeded" >&2
  else
    merge_error="merge by hand once every task is done: $TREEDYN merge -o $OUT $PARTS/part_*.part"
    reply="$(cat "$scratch/sbatch") $reply"
    echo "$(stamp) error: MERGE=1, but the merge job could not be queued; sbatch ${flags[*]} said: ${reply//$'\n'/ }" >&2
    echo "$(stamp) this task runs its part all the same; $merge_error" >&2
  fi
}

if [ "$task" -eq 0 ] && [ "$MERGE" = 1 ]; then
  earlier_merges
  queue_merge
fi

# Stop signals, the launcher's stderr and its exit code as in slurm_ensemble.sh.
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
    echo "$(stamp) SIG$1: stopping task $task" >&2
    [ -z "$ranks" ] || kill -USR1 "$ranks" 2>/dev/null || true
  else
    echo "$(stamp) SIG$1 while stopping (on SIG$stop): waiting for the ranks" >&2
  fi
}
stderr_copy=$scratch/stderr
touch "$scratch/launched"
trap '' USR1 TERM INT HUP
exec 3> >(exec tee -a "$stderr_copy" >&2)
tee_pid=$!
trap 'stop_on USR1' USR1
trap 'stop_on TERM' TERM
trap 'stop_on INT' INT
trap 'stop_on HUP' HUP

"${launcher[@]}" "$TREEDYN" "$JOB" -o "$part" --samples "$first:$end" --resume \
  --checkpoint-every "$CHECKPOINT_EVERY" --progress-interval 60 2>&3 &
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
for _ in $(seq 100); do kill -0 "$tee_pid" 2>/dev/null || break; sleep 0.1; done

# Rank 0's line on the launcher's stderr, or in CHECKPOINT/stopped if this
# run left one there (for a launcher that does not show what the ranks print
# once it ends the job itself).
clean_stop='^interrupted by SIG[A-Z0-9]+ after [0-9]+ of [0-9]+ samples; resume with --resume'
stopped_line=$(grep -E "$clean_stop" "$stderr_copy" | tail -n 1 || true)
if [ -z "$stopped_line" ] && [ "$part.checkpoint/stopped" -nt "$scratch/launched" ]; then
  stopped_line=$(grep -E "$clean_stop" "$part.checkpoint/stopped" | tail -n 1 || true)
fi
if [ "$status" -ne 0 ] && [ "$status" -ne 5 ] && [ -n "$stopped_line" ]; then
  echo "$(stamp) $LAUNCH exited $status after ending the job itself, but rank 0 reported a clean stop: exit 5" >&2
  status=5
fi
if [ "$status" -eq 5 ]; then
  if [ "$stop" = USR1 ] && [ -z "$cancelled" ]; then
    echo "$(stamp) interrupted: requeueing task ${SLURM_ARRAY_JOB_ID}_${task} to resume" >&2
    scontrol requeue "${SLURM_ARRAY_JOB_ID}_${task}" ||
      echo "$(stamp) error: scontrol requeue ${SLURM_ARRAY_JOB_ID}_${task} failed: submit the same array again to resume" >&2
  else
    echo "$(stamp) interrupted${stop:+ (SIG${cancelled:-$stop})}: submit the same array again to resume" >&2
  fi
elif [ "$status" -eq 0 ] && [ -n "$merge_error" ]; then
  echo "$(stamp) error: part $task is done, but the merge job could not be queued (MERGE=1, see above): $merge_error" >&2
  status=2
fi
exit "$status"
