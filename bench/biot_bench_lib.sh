# Shared pieces of the Biot benchmarks (sourced by bench/run_bench_biot.sh
# and bench/run_bench_standins.sh): the &solver settings of each
# preconditioner variant and the figures read back from a run's log.

# biot_solver VARIANT: the &solver variables of a variant, FGMRES to 1e-8
# with the elastic reference solve of K (CG + BoomerAMG) in the same run
#   implicit      : implicit factors, ldu_cheap, fixed stress + scaled Laplacian, AMG
#   explicit_amg  : block aFSAI factors F, explicit Schur P + F1'K F1 + g F2'A F2, AMG on K and S
#   explicit_afsai: the same with our aFSAI on K, A and S (the seed's all-aFSAI method)
#   mumps         : MUMPS over all ranks (the layout of the benchmark reports' MUMPS columns)
biot_solver() {
  local fgmres="method = 'fgmres', precon = 'block', rtol = 1.0e-8, elastic_reference = .true."
  case $1 in
    implicit) echo "$fgmres" ;;
    explicit_amg) echo "$fgmres, decoupling = 'explicit'" ;;
    explicit_afsai) echo "$fgmres, decoupling = 'explicit', k_precon = 'afsai', flux_precon = 'afsai', schur_precon = 'afsai', restart = 300, max_iter = 5000" ;;
    mumps) echo "method = 'mumps', mumps_layout = 'distributed'" ;;
    *) echo "biot_solver: unknown variant '$1'" >&2; return 1 ;;
  esac
}

# parse_biot_log LOG: from the first step line and the lines around it (and
# /usr/bin/time -v's report in the same file) set tot (unknowns), its, rres
# (final relative residual), tp1, tp2, ts (set-up parts and solve [s]), ref
# ("its / setup / solve" of the elastic reference), refs (its solve [s]),
# ratio (ts / refs), mu (preconditioner density), rss (largest rank's peak
# resident memory [MB]), conv ("yes" or "no": a 'did not converge' warning)
parse_biot_log() {
  local log=$1 step
  tot=$(grep -m1 '^unknowns' "$log" | sed -E 's/.*total ([0-9]+).*/\1/')
  step=$(grep -m1 '^step' "$log")
  its=$(echo "$step" | sed -E 's/.*iterations +([0-9]+).*/\1/')
  rres=$(echo "$step" | sed -E 's/.*rel. residual +([0-9.eE+-]+).*/\1/')
  tp1=$(echo "$step" | sed -E 's/.*setup\(dt-indep.\) +([0-9.]+) s.*/\1/')
  tp2=$(echo "$step" | sed -E 's/.*setup\(dt\) +([0-9.]+) s.*/\1/')
  ts=$(echo "$step" | sed -E 's/.*solve +([0-9.]+) s.*/\1/')
  ref=$(grep -m1 'elastic reference' "$log" | sed -E 's/.*iterations ([0-9]+),.*AMG setup +([0-9.]+) s, solve +([0-9.]+) s.*/\1 \/ \2 \/ \3/')
  refs=$(grep -m1 'elastic reference' "$log" | sed -E 's/.*solve +([0-9.]+) s.*/\1/')
  ratio="-"
  [ -n "$refs" ] && [ -n "$ts" ] && ratio=$(awk -v a="$ts" -v b="$refs" 'BEGIN {printf "%.2f", a / b}')
  mu=$(grep -m1 'density mu' "$log" | sed -E 's/.*density mu ([0-9.eE+-]+).*/\1/')
  rss=$(grep -m1 'Maximum resident set size' "$log" | awk '{print int($NF/1024)}')
  conv=yes
  grep -q 'did not converge' "$log" && conv=no
  return 0
}
