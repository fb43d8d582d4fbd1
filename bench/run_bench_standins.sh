#!/usr/bin/env bash
# The seed's Biot cases, Treporti and Reservoir, on our stand-ins
# (input/treporti.nml: 401,777 unknowns; input/reservoir.nml: 1,525,702):
# one time step of gamma = dt from rest (undrained = .false.), FGMRES to
# 1e-8 with each preconditioner variant (bench/biot_bench_lib.sh), the set-up
# split into its dt-independent (T_p1) and dt-dependent (T_p2) parts, one
# CG + BoomerAMG solve of K on the same mesh in the same run as the
# reference; a variant that does not converge within max_iter is reported so
# (fail_on_no_convergence = .false.). Then MUMPS on Treporti at one gamma.
# Usage: bench/run_bench_standins.sh [cases] [ranks] [gammas] [variants] [mumps gamma, 'no': none]
# Writes build/bench/standins.md (TABLE=path: elsewhere). LIMIT=seconds
# stops a run after that long (its row says so; default: no limit).
set -u
cd "$(dirname "$0")/.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
cases=${1:-"treporti reservoir"}
np=${2:-2}
gammas=${3:-"864 86400 8640000"}
variants=${4:-"implicit explicit_amg explicit_afsai"}
mumps_gamma=${5:-86400}
# shellcheck source=bench/biot_bench_lib.sh
. bench/biot_bench_lib.sh
out=build/bench
mkdir -p "$out"
table=${TABLE:-$out/standins.md}
limit=${LIMIT:-0}
# the seed's aFSAI iterations at gamma = 0.01, 1, 100 days
seed_its() {
  case $1:$2 in
    treporti:864) echo 272 ;; treporti:86400) echo 183 ;; treporti:8640000) echo 91 ;;
    reservoir:864) echo 299 ;; reservoir:86400) echo 182 ;; reservoir:8640000) echo 182 ;;
    *) echo "" ;;
  esac
}
{ echo "| case | unknowns | ranks | variant | gamma [s] | mu | iterations | T_p1 [s] | T_p2 [s] | T_s [s] | elastic AMG: its / setup / solve [s] | T_s / elastic solve | peak RSS of a rank [MB] | seed (aFSAI): its |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"; } > "$table"
for c in $cases; do
  for s in $variants mumps; do
    for g in $gammas; do
      [ "$s" = mumps ] && [ "$g" != "$mumps_gamma" ] && continue
      [ "$s" = mumps ] && [ "$c" != treporti ] && continue
      name=${c}_${s}_np${np}_g${g}
      solver=$(biot_solver "$s") || exit 1
      # FGMRES: a step that does not converge is a result, not a stop
      keep="/^&solver/a\\  fail_on_no_convergence = .false."
      [ "$s" = mumps ] && keep=""
      sed -e "s#^ *times = .*#  dt = $g, t_end = $g, undrained = .false.#" -e '/^ *undrained = /d' \
          ${keep:+-e "$keep"} \
          -e "s#method = 'fgmres', precon = 'block', rtol = 1.0e-8#$solver#" \
          -e "s#dir = 'out', prefix = '$c'#dir = '$out/$name', prefix = '$c', fields = .false.#" \
          "input/$c.nml" > "$out/$name.nml"
      log=$out/$name.log
      if [ "$limit" -gt 0 ]; then
        /usr/bin/time -v timeout "$limit" mpirun --oversubscribe -np "$np" bin/geoblock "$out/$name.nml" > "$log" 2>&1
      else
        /usr/bin/time -v mpirun --oversubscribe -np "$np" bin/geoblock "$out/$name.nml" > "$log" 2>&1
      fi
      rc=$?
      parse_biot_log "$log"
      [ "$conv" = no ] && its="$its (not converged: rel. res. $rres)"
      [ -z "$its" ] && its="(failed, see $log)"
      [ "$limit" -gt 0 ] && [ "$rc" -eq 124 ] && its="(stopped after $limit s)"
      printf '| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n' "$c" "$tot" "$np" "$s" "$g" \
        "${mu:--}" "$its" "$tp1" "$tp2" "$ts" "${ref:--}" "$ratio" "$rss" "$(seed_its "$c" "$g")" | tee -a "$table"
    done
  done
done
echo "table: $table"
