#!/usr/bin/env bash
# Rank 0's capacity (BENCHMARKS.md, "Rank 0's capacity"): for each shipped
# example, runs of 2 to 64 oversubscribed ranks, and from their files rank
# 0's CPU time per record it took in (receiving, decoding, writing: the
# attribute record_writing_cpu_seconds_per_rank), the samples' own CPU time
# (busy_cpu_seconds_per_rank), both per sample between a run of N and one of
# 4 N samples, and the ranks that would keep rank 0 fully busy with records
# alone: sample CPU / record CPU.
# CPU time, not wall time, so that oversubscribed ranks do not distort it.
# (The work queue's requests cost rank 0 nothing measurable on one node:
# they are one-sided atomics in an MPI window, done by the requesting rank;
# two runs of block size 1 and 64 differed by less than the noise of rank
# 0's CPU spent waiting in MPI. BENCHMARKS.md says more.)
#
# EXAMPLES="spherical_pendulum crane_payload" picks examples; SAMPLES=N
# sets N for all of them; UNIT_ROWS=R makes senders send units of R rows
# (whole compressed chunks, ensemble/capacity.hpp) whatever N and the
# ranks, through the hidden --test-unit-rows (a run chooses R itself from
# its samples and ranks; N must then be many times ranks x R, so that
# rank 0's own samples, written as records, are a small share).
#
#   bash bench/capacity_benchmark.sh [BUILD_DIR] [RANKS...]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
shift || true
ranks=("$@")
[ ${#ranks[@]} -gt 0 ] || ranks=(2 4 8 16 32 64)
ensemble=$build/mpi/treedyn-ensemble
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# Samples per example (N; each P runs N and 4 N): about 10-60 s of CPU (the
# crane's are Saltelli's base points: 69 runs each).
declare -A samples=([spherical_pendulum]=4096 [double_pendulum]=1024 [chain10]=512 [y_tree]=512
                    [crane_payload]=2 [kapitza]=1024)

# FILE -> "record_cpu_s sample_cpu_s other_cpu_s samples unit_storing_cpu_s samples_in_units
# stored_bytes_per_sample" from its root attributes (sums over the run) and its datasets.
measure() {
  /usr/bin/python3 - "$1" <<'PY'
import sys, h5py
with h5py.File(sys.argv[1]) as f:
    a = f.attrs
    writing, busy, cpu = a["record_writing_cpu_seconds_per_rank"], a["busy_cpu_seconds_per_rank"], a["cpu_seconds_per_rank"]
    sizes = []  # the per-sample numbers' stored bytes (deflated where that paid)
    f["samples"].visititems(lambda name, o: sizes.append(o.id.get_storage_size())
                            if isinstance(o, h5py.Dataset) and o.dtype.kind in "fiu" else None)
    stored = sum(sizes)
    print(f"{writing[0]:.6f} {busy.sum():.6f} {cpu[0] - busy[0] - writing[0]:.6f} {int(a['samples_used'])} "
          f"{a['unit_storing_cpu_seconds']:.6f} {int(a['samples_in_units'])} {stored / int(a['samples_used']):.0f}")
PY
}

# JOB N BLOCK OUT -> a copy of JOB with samples = N, the block size BLOCK, no stored trajectories
edited() {
  sed -E -e "s/^samples = [0-9]+/samples = $2\nblock_size = $3/" -e "s/^store_trajectories = [0-9]+//" "$1" > "$4"
}

# Rank 0's record writing has a part that does not grow with the samples
# (the first chunks of each dataset are always deflated, to judge whether
# deflate pays); the marginal cost, between N and 4 N samples, is what a
# long run pays per record.
echo "| example | record (bytes) | row bytes | stored (bytes) | ranks | rank 0 CPU per record (us) | of which storing units (us per unit record) | writing here (ns/byte) | sample CPU (ms) | scales to (ranks) |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
for name in ${EXAMPLES:-spherical_pendulum double_pendulum chain10 y_tree crane_payload kapitza}; do
  n=${SAMPLES:-${samples[$name]}}
  for p in "${ranks[@]}"; do
    for m in "$n" "$((4 * n))"; do
      edited "jobs/$name.toml" "$m" 4 "$work/$name.toml"
      mpirun -np "$p" --oversubscribe "$ensemble" "$work/$name.toml" -o "$work/run_$m.h5" -q --checkpoint-every 0 \
        ${UNIT_ROWS:+--test-unit-rows "$UNIT_ROWS"} > /dev/null 2>&1
    done
    read -r w1 b1 _ r1 s1 u1 _ <<< "$(measure "$work/run_$n.h5")"
    read -r w4 b4 _ r4 s4 u4 stored <<< "$(measure "$work/run_$((4 * n)).h5")"
    # The record's size, its row bytes and what writing costs here, measured
    # now in the runs' directory (ensemble/capacity.hpp's model has a part
    # per row byte at that cost: BENCHMARKS.md, "Rank 0's storing is the
    # page cache's").
    check=$("$ensemble" --check "$work/$name.toml" -o "$work/check.h5")
    bytes=$(sed -n 's/.*(\([0-9]*\) bytes each.*/\1/p' <<< "$check")
    row_bytes=$(sed -n 's/.*; \([0-9]*\) row bytes a record, about.*/\1/p' <<< "$check")
    write_ns=$(sed -n 's/.* \([0-9.]*\) ns a byte of page-cache CPU measured now.*/\1/p' <<< "$check")
    /usr/bin/python3 -c "
record = ($w4 - $w1) / ($r4 - $r1)
sample = ($b4 - $b1) / ($r4 - $r1)
storing = f'{($s4 - $s1) / ($u4 - $u1) * 1e6:.2f}' if $u4 > $u1 else '-'
print(f'| $name | $bytes | $row_bytes | $stored | $p | {record * 1e6:.2f} | {storing} | $write_ns | {sample * 1e3:.3f} | {int(sample / record)} |')"
    rm -f "$work"/run_*.h5
  done
done

