#!/usr/bin/env bash
# Hydraulically active fractures (issue 14): the seed's nine-fracture
# injection case (input/nine_fractures.nml; its reduced version
# tests/decks/flow_nine.nml) with FGMRES and the u-t-p block preconditioner,
# against MUMPS on the same deck, and beside the contact-only systems of the
# same mesh (physics 'contact', the fluid pressure of each phase given as a
# fault pressure: 4 MPa stick, 7 MPa slip).
# Per case: for every time step the statuses, Newton iterations, FGMRES
# iterations of each linear system, set-up and solve seconds; MUMPS: time and
# the peak resident memory from the timing summary. Levels: cells per side
# (17 = the reduced case, 4 m cells; 34; 68 = the seed's size, 1 m cells,
# with nz = 69). Each run is cut at `limit` seconds (the seed's size with
# FGMRES does not finish in a bench's time: see doc/benchmarks-history.md).
# Usage: bench/run_bench_flow.sh [levels] [ranks] [limit seconds] [t_end] [solvers]
# (solvers: any of mumps schur schur300 eliminated contact; all by default)
set -u
cd "$(dirname "$0")/.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
levels=${1:-"17 34"}
np=${2:-2}
limit=${3:-1800}
t_end=${4:-"15.0"}
solvers=${5:-"mumps schur schur300 eliminated contact"}
out=build/bench/flow
mkdir -p "$out"
cp tests/decks/nine_fractures_rate.tab "$out/"
table=build/bench/flow.md
echo "| cells per side | u / t unknowns | solver | step: stick/slip/open, Newton, linear its per Newton | setup [s] | solve [s] | peak memory |" > "$table"
echo "|---|---|---|---|---|---|---|" >> "$table"

deck() {  # level solver physics pressure -> deck on stdout
  local n=$1 solver=$2 phys=$3 press=${4:-}
  local nz=$n up="68.0, 68.0, 68.0"
  [ "$n" = 68 ] && { nz=69; up="68.0, 68.0, 69.0"; }
  sed -e "s#dir = 'out'#dir = '$out'#" -e "s#nx = 17, ny = 17, nz = 17#nx = $n, ny = $n, nz = $nz#" \
      -e "s#upper = 68.0, 68.0, 68.0#upper = $up#" -e "s#method = 'mumps'#$solver#" \
      -e "s#t_end = 15.0#t_end = $t_end#" tests/decks/flow_nine.nml |
  if [ "$phys" = contact ]; then
    # the same mesh and stress, the fluid pressure a fixed fault pressure
    awk -v p="$press" '
      /^&fracture_flow/ || /^&well/ {skip = 1}
      skip && /^\/$/ {skip = 0; next}
      skip {next}
      /^&time/ {print "&time\n  n_steps = 1\n/"; t = 1; next}
      t && /^\/$/ {t = 0; next}
      t {next}
      {sub(/physics = .fracture_flow./, "physics = '\''contact'\''")
       sub(/friction_angle = 30.0/, "friction_angle = 30.0, pressure = " p); print}'
  else
    cat
  fi
}

summary() {  # log -> per step "step: s/s/o, N, its..."
  awk '/^time step|^load step/ {
         match($0, /stick\/slip\/open [0-9\/]+/); st = substr($0, RSTART + 16, RLENGTH - 16)
         match($0, /newton +[0-9]+/); nw = substr($0, RSTART + 6, RLENGTH - 6); gsub(/ /, "", nw)
         printf "%s %s, %s, %s; ", $3, st, nw, its; its = ""; next}
       /linear its/ {its = its $5 " "}' "$1"
}

row() {  # level solver label log
  local log=$2
  local unk setup solve mem
  unk=$(grep -m1 "^unknowns" "$log" | sed -E 's/unknowns: u ([0-9]+), t ([0-9]+).*/\1 \/ \2/')
  setup=$(awk '/^time step|^load step/ {match($0, /setup +[0-9.]+/); s += substr($0, RSTART + 6, RLENGTH - 6)} END {printf "%.1f", s}' "$log")
  solve=$(awk '/^time step|^load step/ {match($0, /solve +[0-9.]+/); s += substr($0, RSTART + 6, RLENGTH - 6)} END {printf "%.1f", s}' "$log")
  mem=$(grep -m1 "MUMPS:.*peak memory" "$log" | sed -E 's/.*peak memory ([0-9]+ MB).*/\1 (MUMPS factorization)/')
  echo "| $1 | $unk | $3 | $(summary "$log") | $setup | $solve | ${mem:-not measured} |" >> "$table"
}

for n in $levels; do
  for s in $solvers; do
    [ "$s" = contact ] && continue
    # MUMPS at the seed's size needs more than this machine's 24 GB (doc/benchmarks.md,
    # the elastic MUMPS table: about 26 GB at 824k unknowns on 2 ranks)
    if [ "$s" = mumps ] && [ "$n" -ge 68 ]; then
      echo "| $n | | fracture flow, mumps | not run: more memory than 24 GB | | | |" >> "$table"
      continue
    fi
    case $s in
      mumps)  solver="method = 'mumps'" ;;
      # the seed's second level (pressure_block = 'schur'): its slipping steps
      # need 100-140 iterations, so restart = 300 keeps the whole Krylov
      # space (the default 100 restarts and needs 2-4x more)
      schur) solver="method = 'fgmres', rtol = 1.0e-8" ;;
      schur300) solver="method = 'fgmres', rtol = 1.0e-8, restart = 300" ;;
      eliminated) solver="method = 'fgmres', rtol = 1.0e-8, elastic_reference = .true." ;;
    esac
    name=nine_${n}_$s
    pb=eliminated; case $s in schur*) pb=schur ;; esac
    deck "$n" "$solver" flow | sed -e "s#prefix = 'flow_nine'#prefix = '$name'#" \
      -e "s#initial_pressure = 4.0e6#initial_pressure = 4.0e6, pressure_block = '$pb'#" > "$out/$name.nml"
    echo "== $name"
    timeout "$limit" mpirun --oversubscribe -np "$np" bin/geoblock "$out/$name.nml" > "$out/$name.stdout" 2>&1 < /dev/null
    echo "   exit $? (124: cut at $limit s)"
    [ -f "$out/$name.log" ] && row "$n" "$out/$name.log" "fracture flow, $s"
  done
  for p in 4.0e6 7.0e6; do
    case " $solvers " in *" contact "*) ;; *) continue ;; esac
    name=nine_${n}_contact_${p%%.*}
    deck "$n" "method = 'fgmres', rtol = 1.0e-8" contact "$p" | sed -e "s#prefix = 'flow_nine'#prefix = '$name'#" > "$out/$name.nml"
    echo "== $name"
    timeout "$limit" mpirun --oversubscribe -np "$np" bin/geoblock "$out/$name.nml" > "$out/$name.stdout" 2>&1 < /dev/null
    echo "   exit $?"
    [ -f "$out/$name.log" ] && row "$n" "$out/$name.log" "contact only, fault pressure $p Pa, fgmres"
  done
done
echo "table: $table"
cat "$table"
