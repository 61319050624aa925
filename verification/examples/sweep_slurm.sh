#!/bin/bash
# A distributed sweep on a Slurm cluster (src/app/README.md, "Sweeps on several machines: MPI"): 1000 cases of
# the 500 m pipeline over 64 ranks, one thread each, one HDF5 file and one CSV written by rank 0.
# Submit from the liftoff source tree (a file system the compute nodes share): sbatch
# verification/examples/sweep_slurm.sh. liftoff must be built against the cluster's MPI (module load
# openmpi, then .ci/setup.sh or cmake as in the README).
#SBATCH --job-name=liftoff-sweep
#SBATCH --ntasks=64
#SBATCH --cpus-per-task=1
#SBATCH --time=01:00:00
#SBATCH --output=liftoff-sweep-%j.log
set -euo pipefail

# srun starts the ranks itself (Slurm's PMIx); with an MPI built without Slurm support, use
# `mpirun liftoff ...` instead, which reads the allocation from Slurm.
srun --mpi=pmix build/src/liftoff sweep verification/scenes/engineering/pipeline_500m_uplift.toml \
  --set "loads[1].value=lin:-20e3:-80e3:1000" --elements 2000 \
  --output "pipeline_sweep_${SLURM_JOB_ID}.h5" --csv "pipeline_sweep_${SLURM_JOB_ID}.csv"
