#!/usr/bin/env bash
# Are two builds' ensemble files the same? Runs every shipped example (and
# the benchmark jobs) with both builds' treedyn-ensemble on 1, 2 and 3 ranks,
# and compares every dataset's values (shape, type, bits) under /stats,
# /samples, /responses, /sensitivity, /rare_event, /integration_check,
# /nominal and /trajectories, and every attribute of those objects and of the
# root (their descriptions, units, verdicts) but what depends on the run
# itself (times, hosts, ranks, the command line, the build), bit for bit (no
# tolerance), plus one sample rerun alone (--sample K): its /final_state and
# /sample/inputs. For a
# refactoring, the older build is the commit before it:
#
#   git worktree add /tmp/before HEAD~1 && cmake -S /tmp/before -B /tmp/before/build \
#     -DTREEDYN_BUILD_BENCHMARKS=OFF && cmake --build /tmp/before/build -j2 --target treedyn-ensemble
#   bash bench/compare_outputs.sh /tmp/before/build build
#
# Usage: [SKIP_ATTRIBUTES="description ..."] bash bench/compare_outputs.sh OLD_BUILD_DIR NEW_BUILD_DIR [JOB ...]
# (SKIP_ATTRIBUTES: attributes a change means to reword, left out everywhere)
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

same() {  # A B GROUP...: every dataset under the named groups bitwise equal in both files (values,
           # shape, type), and every attribute of them, of their groups and of the root but the run's own
  /usr/bin/python3 - "$@" <<'PY'
import os, sys, h5py, numpy as np
# What a run records of itself: when, where, on how many ranks, by which command and build, how fast.
RUN_OWN = {"start_utc", "end_utc", "wall_time_seconds", "wall_seconds", "command_line", "git_commit", "build_type",
           "compiler", "host", "rank_hosts", "ranks", "samples_per_rank", "samples_run_here", "cpu_seconds_per_rank",
           "busy_seconds_per_rank", "busy_cpu_seconds_per_rank", "record_writing_seconds_per_rank",
           "record_writing_cpu_seconds_per_rank", "peak_rss_mib_per_rank", "unit_storing_cpu_seconds",
           "samples_per_second", "unit_rows", "samples_in_units", "output_file", "job_file"}
RUN_OWN |= set(os.environ.get("SKIP_ATTRIBUTES", "").split())
a, b, groups = h5py.File(sys.argv[1], "r"), h5py.File(sys.argv[2], "r"), sys.argv[3:]
def objects(f, g):
    out = {}
    if g in f:
        out[g] = f[g]
        if isinstance(f[g], h5py.Group): f[g].visititems(lambda n, o: out.__setitem__(g + "/" + n, o))
    return out
def bits(v):
    v = np.asarray(v)  # strings come as objects, whose bytes are pointers: compare the values
    return (v.shape, v.dtype.str, v.tolist() if v.dtype == object else v.tobytes())
def same_attributes(name, x, y):
    keys = (set(x.attrs) | set(y.attrs)) - RUN_OWN
    for k in sorted(keys):
        if k not in x.attrs or k not in y.attrs or bits(x.attrs[k]) != bits(y.attrs[k]):
            print(f"differs in {name or '/'}: attribute {k}"); sys.exit(1)
same_attributes("", a, b)
for g in groups:
    da, db = objects(a, g), objects(b, g)
    if da.keys() != db.keys():
        print(f"differs in {g}: objects {sorted(set(da) ^ set(db))}"); sys.exit(1)
    for name in da:
        same_attributes(name, da[name], db[name])
        if isinstance(da[name], h5py.Dataset) and bits(da[name][()]) != bits(db[name][()]):
            print(f"differs in {name}"); sys.exit(1)
PY
}

for job in "${jobs[@]}"; do
  grep -q '^\[ensemble\]' "$job" || continue
  name=$(basename "$job" .toml)
  run "$old" 1 "$job" "$work/$name.old.h5" || { echo "$name: the old build failed: $(cat "$work/$name.old.h5.err")"; status=1; continue; }
  for ranks in 1 2 3; do
    out="$work/$name.new$ranks.h5"
    if ! run "$new" "$ranks" "$job" "$out"; then echo "$name, $ranks ranks: the new build failed: $(cat "$out.err")"; status=1; continue; fi
    groups=(/stats /samples /responses /sensitivity /rare_event /integration_check /nominal /trajectories)
    if why=$(same "$work/$name.old.h5" "$out" "${groups[@]}"); then
      echo "$name, $ranks rank(s): every dataset and attribute of ${groups[*]} and the root bitwise equal (where present)"
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
