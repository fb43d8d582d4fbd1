#!/usr/bin/env bash
# The machine's memory bandwidth on 1 and more ranks (tools/triad.f90) and
# our CSR product's on the pattern of Mandel at the seed's size
# (tools/spmv.f90), to read strong-scaling figures against: sparse products
# and AMG V-cycles are bound by it. Run it with nothing else on the machine.
# Usage: tools/bandwidth.sh [ranks ...]   (default: 1 2; three runs each)
# FFLAGS in the environment replaces the flags (default: those of the
# project's optimized build, Makefile).
set -eu
cd "$(dirname "$0")/.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
mkdir -p build/tools
flags=${FFLAGS:--O3 -march=x86-64-v2}
mpif90 $flags tools/triad.f90 -o build/tools/triad
mpif90 $flags tools/spmv.f90 -o build/tools/spmv
for run in 1 2 3; do
  for np in ${*:-1 2}; do
    mpirun -np "$np" build/tools/triad
    mpirun -np "$np" build/tools/spmv
  done
done
