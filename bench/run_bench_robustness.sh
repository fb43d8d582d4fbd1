#!/usr/bin/env bash
# Robustness matrix of the fluid in the fractures (issue 31): every
# combination of residual aperture (1e-5 to 1e-2 m), element size (1 mm to
# 1 m), fluid compressibility (0, 1e-14 to 1e-8 1/Pa), time step (1e-3 to
# 1e3 s), closed and open fracture, 1 and 2 ranks (768 runs of a plane
# strain fracture of 20 elements, MUMPS; tests/robustness/matrix.py) must
# either run to the end or be refused before the first step as singular.
# The table gives each case's outcome, Newton iterations per step and
# linear iterations (refinement steps of the direct solves). make test runs
# a corner subset of it (tests/robustness/robustness.sh).
# Usage: bench/run_bench_robustness.sh [jobs]
set -u
cd "$(dirname "$0")/.."
out=build/bench
mkdir -p "$out"
table=$out/robustness.md
/usr/bin/python3 tests/robustness/matrix.py --full --jobs "${1:-2}" --out "$out/robustness" --table "$table" | tail -3
echo "table: $table"
