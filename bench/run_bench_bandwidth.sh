#!/usr/bin/env bash
# The bandwidth the solve phase reaches (issue 34, goal 5): the machine's
# triad (tools/triad.f90) and, in the same run, CG + BoomerAMG on the clamped
# cube of bench/run_bench.sh (n = 64: 823,875 unknowns, to 1e-8) with
# l1 Gauss-Seidel (every physics' default, in geoblock's own cycle:
# &amg cycle_code = 'geoblock', on single-precision level values), the same
# with double values (l1-gs:double), in hypre's cycle (l1-gs:hypre,
# whose backward sweep reads memory against the prefetch), Chebyshev and
# l1 Jacobi (the bytes of Gauss-Seidel, no order between the rows), on 1
# and 2 ranks. The bytes an iteration moves (our matrix, hypre's
# hierarchy, the vectors) come from hypre's set-up statistics
# (&amg print_level = 1) and the model in bench/solve_bytes.py; the rate is
# those bytes times the iterations over the solve time, the share its ratio
# to the triad of as many ranks.
# Usage: bench/run_bench_bandwidth.sh [n] [ranks] [smoothers]
set -u
cd "$(dirname "$0")/.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
n=${1:-64}
ranks=${2:-"1 2"}
smoothers=${3:-"l1-gs l1-gs:double l1-gs:hypre chebyshev l1-jacobi"}
PY=${PYTHON:-/usr/bin/python3}
out=build/bench
mkdir -p "$out" build/tools
table=$out/bandwidth.md
mpif90 -O3 -march=x86-64-v2 tools/triad.f90 -o build/tools/triad || exit 2
{
  echo "| ranks | smoother | triad, all ranks [GB/s] | CG iterations | solve [s] | per iteration [s] | our matrix [MB/it] | hierarchy [MB/it] | vectors [MB/it] | total [MB/it] | solve rate [GB/s] | share of the triad |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
} > "$table"
for np in $ranks; do
  triad=$(mpirun --oversubscribe -np "$np" build/tools/triad | sed -E 's/.*all ranks +([0-9.]+).*/\1/')
  for entry in $smoothers; do
    sm=${entry%%:*}
    code=geoblock
    prec=single
    label=$sm
    case $entry in
      *:hypre) code=hypre; prec=double; label="$sm (hypre's cycle)" ;;
      *:double) prec=double; label="$sm (double values)" ;;
    esac
    name=bandwidth_${n}_${sm}_${code}_${prec}_np${np}
    sed -e "s#nx = 16, ny = 16, nz = 16#nx = $n, ny = $n, nz = $n#" \
        -e "s#n_steps = 2 .*#n_steps = 1#" \
        -e "s#dir = 'out'.*#dir = '$out/$name', fields = .false.#" \
        input/cube.nml > "$out/$name.nml"
    printf "&amg\n  relax_type = '%s', print_level = 1, cycle_code = '%s', precision = '%s'\n/\n" "$sm" "$code" \
      "$prec" >> "$out/$name.nml"
    log=$out/$name.log
    mpirun --oversubscribe -np "$np" bin/geoblock "$out/$name.nml" > "$log" 2>&1 < /dev/null
    rc=$?
    if [ $rc -ne 0 ]; then
      echo "| $np | $label | $triad | failed (exit $rc, $log) | | | | | | | | |" | tee -a "$table"
      continue
    fi
    row=$($PY bench/solve_bytes.py "$log" "$triad") || row="parse failed ($log) | | | | | | | |"
    echo "| $np | $label | $triad | $row |" | tee -a "$table"
  done
done
echo "table: $table"
