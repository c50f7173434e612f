#!/usr/bin/env bash
# Are two builds' ensemble files the same? Runs every shipped example (and
# the benchmark jobs) with both builds' treedyn-ensemble on 1, 2 and 3 ranks,
# and compares /stats, /samples, /responses and /sensitivity with h5diff (bit
# for bit: no tolerance), plus one sample rerun alone (--sample K) and its
# /final_state. For a refactoring, the older build is the commit before it:
#
#   git worktree add /tmp/before HEAD~1 && cmake -S /tmp/before -B /tmp/before/build \
#     -DTREEDYN_BUILD_BENCHMARKS=OFF && cmake --build /tmp/before/build -j2 --target treedyn-ensemble
#   bash bench/compare_outputs.sh /tmp/before/build build
#
# Usage: bash bench/compare_outputs.sh OLD_BUILD_DIR NEW_BUILD_DIR [JOB ...]
# (a build directory, or a directory holding the treedyn-ensemble binary).
# Prints one line per comparison and exits non-zero if any differs.
set -uo pipefail
cd "$(dirname "$0")/.."
binary() { if [ -x "$1/mpi/treedyn-ensemble" ]; then echo "$1/mpi/treedyn-ensemble"; else echo "$1/treedyn-ensemble"; fi; }
old=$(binary "${1:?usage: compare_outputs.sh OLD_BUILD NEW_BUILD [JOB ...]}")
new=$(binary "${2:?usage: compare_outputs.sh OLD_BUILD NEW_BUILD [JOB ...]}")
shift 2
jobs=("$@")
[ ${#jobs[@]} -gt 0 ] || jobs=(jobs/*.toml bench/jobs/heterogeneous.toml)
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
status=0

run() {  # BINARY RANKS JOB OUT
  if [ "$2" -eq 1 ]; then "$1" "$3" -o "$4" -q --checkpoint-every 0 >/dev/null 2>"$4.err"
  else mpirun --oversubscribe -np "$2" "$1" "$3" -o "$4" -q --checkpoint-every 0 >/dev/null 2>"$4.err"; fi
}

same() {  # A B GROUP...: every named group bitwise equal (a group absent from both counts as equal)
  local a=$1 b=$2; shift 2
  for g in "$@"; do
    if h5ls "$a$g" >/dev/null 2>&1 || h5ls "$b$g" >/dev/null 2>&1; then
      h5diff -q "$a" "$b" "$g" "$g" >/dev/null 2>&1 || { echo "differs in $g"; return 1; }
    fi
  done
}

for job in "${jobs[@]}"; do
  grep -q '^\[ensemble\]' "$job" || continue
  name=$(basename "$job" .toml)
  run "$old" 1 "$job" "$work/$name.old.h5" || { echo "$name: the old build failed: $(cat "$work/$name.old.h5.err")"; status=1; continue; }
  for ranks in 1 2 3; do
    out="$work/$name.new$ranks.h5"
    if ! run "$new" "$ranks" "$job" "$out"; then echo "$name, $ranks ranks: the new build failed: $(cat "$out.err")"; status=1; continue; fi
    if why=$(same "$work/$name.old.h5" "$out" /stats /samples /responses /sensitivity /nominal); then
      echo "$name, $ranks rank(s): /stats /samples /responses /sensitivity /nominal bitwise equal"
    else
      echo "$name, $ranks rank(s): $why"; status=1
    fi
  done
  k=3
  "$old" "$job" --sample $k -o "$work/$name.sample.old.h5" -q >/dev/null 2>&1
  "$new" "$job" --sample $k -o "$work/$name.sample.new.h5" -q >/dev/null 2>&1
  if why=$(same "$work/$name.sample.old.h5" "$work/$name.sample.new.h5" /final_state /sample/inputs); then
    echo "$name, --sample $k: /final_state and /sample/inputs bitwise equal"
  else
    echo "$name, --sample $k: $why"; status=1
  fi
done
exit $status
