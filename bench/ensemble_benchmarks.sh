#!/usr/bin/env bash
# Ensemble benchmarks for BENCHMARKS.md: peak memory per rank for N and 10 N
# samples, and throughput on 1 and 2 ranks for a job whose samples differ
# in cost by about 10x. Usage: bash bench/ensemble_benchmarks.sh [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
ensemble=$build/mpi/treedyn-ensemble
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

attribute() {  # FILE NAME -> the attribute's value(s), comma-separated
  h5dump -a "$2" "$1" | sed -n '/DATA {/,/}/p' | grep -E '^\s+\(' | sed -E 's/^\s+\([0-9]+\): //' | tr -d ' '
}

with_samples() {  # JOB N OUT -> a copy of JOB with samples = N
  sed -E "s/^samples = [0-9]+/samples = $2/" "$1" > "$3"
}

echo "## Memory per rank (bench/jobs/memory.toml, 2 ranks)"
echo
echo "| samples | peak RSS rank 0 (MiB) | peak RSS rank 1 (MiB) | wall (s) |"
echo "|---:|---:|---:|---:|"
for n in 2000 20000; do
  with_samples bench/jobs/memory.toml "$n" "$work/memory_$n.toml"
  mpirun -np 2 --oversubscribe "$ensemble" "$work/memory_$n.toml" -o "$work/memory_$n.h5" -q > /dev/null 2>&1
  rss=$(attribute "$work/memory_$n.h5" peak_rss_mib_per_rank)
  wall=$(attribute "$work/memory_$n.h5" wall_time_seconds)
  printf '| %s | %s | %s | %.1f |\n' "$n" "${rss%%,*}" "${rss##*,}" "$wall"
done
echo
echo "## Throughput (bench/jobs/heterogeneous.toml, 200 samples, steps per sample min/median/max below)"
echo
echo "| ranks | wall (s) | samples/s | samples per rank | busy s per rank | record writing s per rank | efficiency |"
echo "|---:|---:|---:|---|---|---|---:|"
base=""
for p in 1 2; do
  mpirun -np "$p" --oversubscribe "$ensemble" bench/jobs/heterogeneous.toml -o "$work/het_$p.h5" -q > /dev/null 2>&1
  wall=$(attribute "$work/het_$p.h5" wall_time_seconds)
  rate=$(python3 -c "print(f'{200/$wall:.2f}')")
  [ -z "$base" ] && base=$rate
  eff=$(python3 -c "print(f'{$rate/($base*$p)*100:.0f} %')")
  printf '| %s | %.2f | %s | %s | %s | %s | %s |\n' "$p" "$wall" "$rate" \
    "$(attribute "$work/het_$p.h5" samples_per_rank)" "$(attribute "$work/het_$p.h5" busy_seconds_per_rank)" \
    "$(attribute "$work/het_$p.h5" record_writing_seconds_per_rank)" "$eff"
done
echo
h5dump -d /samples/integrator_stats -y -w 200 "$work/het_1.h5" | grep -E '^\s+[0-9]' | awk -F',' '{print $1+0}' | sort -n |
  awk '{a[NR]=$1} END {printf "steps per sample: min %d, median %d, max %d (max/min %.1f)\n", a[1], a[int(NR/2)], a[NR], a[NR]/a[1]}'
