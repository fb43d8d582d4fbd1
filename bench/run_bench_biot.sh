#!/usr/bin/env bash
# Poromechanics benchmark (issue 3): Mandel's problem (quarter model of
# input/mandel.nml, nz = n/10 layers of cubes) at the seed's size 80 x 80 x 8
# (389,627 unknowns before boundary conditions) and at 40 x 40 x 4, one time
# step with gamma = dt = 0.15, 1 and 100 s, on 1 and 2 ranks: FGMRES + the
# block preconditioner (LDU, fixed stress) to 1e-8, with the set-up split into
# its dt-independent (T_p1) and dt-dependent (T_p2) parts, one CG + BoomerAMG
# elasticity solve on the same mesh as the reference, and MUMPS on the same
# system. Preconditioner variants (issue 4, the seed's table side by side):
#   implicit      : implicit factors, ldu_cheap, fixed stress + scaled Laplacian, AMG
#   explicit_amg  : block aFSAI factors F, explicit Schur P + F1'K F1 + g F2'A F2, AMG on K and S
#   explicit_afsai: the same with our aFSAI on K, A and S (the seed's all-aFSAI method)
# Usage: bench/run_bench_biot.sh [sizes] [ranks] [gammas] [mumps: yes|no] [variants]
set -u
cd "$(dirname "$0")/.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
sizes=${1:-"40 80"}
ranks=${2:-"1 2"}
gammas=${3:-"0.15 1 100"}
with_mumps=${4:-yes}
variants=${5:-"implicit explicit_amg explicit_afsai"}
# shellcheck source=bench/biot_bench_lib.sh
. bench/biot_bench_lib.sh
out=build/bench
mkdir -p "$out"
table=$out/mandel.md
echo "| mesh | unknowns | ranks | solver | gamma | mu | iterations | T_p1 [s] | T_p2 [s] | T_s [s] | elastic AMG: its / setup / solve [s] | T_s / elastic solve | max RSS of a rank [MB] |" > "$table"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|" >> "$table"
for n in $sizes; do
  nz=$((n / 10))
  for np in $ranks; do
    for s in $variants mumps; do
      [ "$s" = mumps ] && [ "$with_mumps" != yes ] && continue
      [ "$s" = mumps ] && [ "$np" != 1 ] && continue
      for g in $gammas; do
        [ "$s" = mumps ] && [ "$g" != 1 ] && continue
        name=mandel_${n}_${s}_np${np}_g${g}
        solver=$(biot_solver "$s") || exit 1
        sed -e "s#nx = 20, ny = 20, nz = 1#nx = $n, ny = $n, nz = $nz#" \
            -e "s#upper = 1.0, 1.0, 0.05#upper = 1.0, 1.0, $(echo "scale=6; $nz / $n" | bc)#" \
            -e "s#dt = 0.05, t_end = 200.0, dt_growth = 1.12, dt_max = 5.0#dt = $g, t_end = $g, undrained = .false.#" \
            -e "s#method = 'fgmres', precon = 'block', rtol = 1.0e-8#$solver#" \
            -e "s#dir = 'out', prefix = 'mandel'#dir = '$out/$name', prefix = 'mandel', fields = .false.#" \
            -e "s#history = 'mandel_plate.tab'#history = '$PWD/input/mandel_plate.tab'#" \
            input/mandel.nml > "$out/$name.nml"
        log=$out/$name.log
        /usr/bin/time -v mpirun --oversubscribe -np "$np" bin/geoblock "$out/$name.nml" > "$log" 2>&1
        parse_biot_log "$log"
        printf '| %sx%sx%s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n' "$n" "$n" "$nz" "$tot" "$np" "$s" \
          "$g" "${mu:--}" "$its" "$tp1" "$tp2" "$ts" "${ref:--}" "$ratio" "$rss" | tee -a "$table"
      done
    done
  done
done
echo "table: $table"
