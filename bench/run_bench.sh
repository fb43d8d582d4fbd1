#!/usr/bin/env bash
# Elasticity benchmark (issue 2): a cube clamped on x = 0 with a shear traction
# on x = 1, refined n = 16, 32, 64 (14,739 / 107,811 / 823,875 unknowns), on 1
# and 2 ranks: CG + BoomerAMG to 1e-8 (iterations, setup, solve) and MUMPS
# (analysis + factorization + solve time, peak memory); amg_w is CG + BoomerAMG
# with W-cycles (&amg cycle_type = 'w', not in the default list).
# Usage: bench/run_bench.sh [sizes] [ranks] [solvers]   e.g. bench/run_bench.sh "16 32" "1 2" "amg amg_w mumps"
set -u
cd "$(dirname "$0")/.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
sizes=${1:-"16 32 64"}
ranks=${2:-"1 2"}
solvers=${3:-"amg mumps"}
out=build/bench
mkdir -p "$out"
table=$out/elasticity.md
echo "| n | unknowns | ranks | solver | iterations | setup [s] | solve [s] | MUMPS peak, all ranks [MB] | max RSS of a rank [MB] |" > "$table"
echo "|---|---|---|---|---|---|---|---|---|" >> "$table"
for n in $sizes; do
  for np in $ranks; do
    for s in $solvers; do
      if [ "$s" = mumps ] && [ "$n" -ge 64 ] && [ "$np" -ge 2 ]; then
        # 2-rank MUMPS at 824k unknowns needs about 26 GB (scaled from 353k)
        echo "| $n | - | $np | mumps | skipped: needs more memory than 24 GB | | | | |" | tee -a "$table"
        continue
      fi
      deck=$out/cube_${n}_${s}_np${np}.nml
      amg_group=""
      case $s in
        amg)   solver="method = 'cg', precon = 'boomeramg', rtol = 1.0e-8" ;;
        amg_w) solver="method = 'cg', precon = 'boomeramg', rtol = 1.0e-8"; amg_group=$'&amg\n  cycle_type = \'w\'\n/' ;;
        mumps) solver="method = 'mumps', mumps_layout = 'distributed'" ;;
      esac
      cat > "$deck" <<DECK
&run
  title = 'bench: cube n = $n, $s, $np ranks'
/
&mesh
  source = 'box', nx = $n, ny = $n, nz = $n
/
&material
  region = 'domain', young = 1.0e10, poisson = 0.25
/
&boundary
  set = 'xmin', type = 'displacement', ux = 0, uy = 0, uz = 0
/
&boundary
  set = 'xmax', type = 'traction', traction = 0, 0, -1.0e6
/
&solver
  $solver
/
&output
  dir = '$out/out_${n}_${s}_np${np}', fields = .false.
/
$amg_group
DECK
      log=$out/cube_${n}_${s}_np${np}.log
      /usr/bin/time -v mpirun --oversubscribe -np "$np" bin/geoblock "$deck" > "$log" 2>&1
      dofs=$(grep -m1 'displacement dofs' "$log" | sed -E 's/.*dofs: ([0-9]+),.*/\1/')
      its=$(grep -m1 '^step 1/' "$log" | sed -E 's/.*iterations +([0-9]+).*/\1/')
      setup=$(grep -m1 '^step 1/' "$log" | sed -E 's/.*setup +([0-9.]+) s.*/\1/')
      solve=$(grep -m1 '^step 1/' "$log" | sed -E 's/.*solve +([0-9.]+) s.*/\1/')
      mem=$(grep -m1 'MUMPS:' "$log" | sed -E 's/.*peak memory ([0-9]+) MB \(max over ranks\), ([0-9]+) MB.*/\2/')
      rss=$(grep -m1 'Maximum resident set size' "$log" | awk '{print int($NF/1024)}')
      [ -z "$mem" ] && mem="-"
      printf '| %s | %s | %s | %s | %s | %s | %s | %s | %s |\n' "$n" "$dofs" "$np" "$s" "$its" "$setup" "$solve" "$mem" "$rss" \
        | tee -a "$table"
    done
  done
done
echo "table: $table"
