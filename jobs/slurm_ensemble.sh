#!/usr/bin/env bash
# SLURM batch script for an ensemble on a cluster. Copy it, set the job file,
# the output and the resources, then: sbatch jobs/slurm_ensemble.sh
# Every rank (rank 0 included) integrates samples; rank 0 also writes the
# file and prints progress lines (every --progress-interval seconds) to the
# job's error log. The results do not depend on the number of ranks.
#SBATCH --job-name=treedyn-ensemble
#SBATCH --ntasks=32
#SBATCH --cpus-per-task=1
#SBATCH --time=02:00:00
#SBATCH --output=treedyn-ensemble-%j.out
#SBATCH --error=treedyn-ensemble-%j.err
set -euo pipefail

JOB=${JOB:-jobs/crane_payload.toml}
OUT=${OUT:-crane_payload_ensemble.h5}

# srun starts the MPI ranks under SLURM (Open MPI built with PMIx support);
# use "mpirun -np $SLURM_NTASKS" instead where srun is not set up for MPI.
srun ./build/mpi/treedyn-ensemble "$JOB" -o "$OUT" --progress-interval 60
