#!/usr/bin/env bash
# Peers on the very same linear systems (issue 15): geoblock exports one
# system of a run (&solver export_step, export_newton: the matrix and
# right-hand side as our FGMRES sees them, with the block of every row) and
# logs its own iterations, set-up and solve for it; bench/peer_petsc.py then
# solves the exported files with PETSc's nested Schur fieldsplit (selfp,
# BoomerAMG with our settings; the outer factorization full, upper or lower,
# whichever is the fastest on 1 rank) on 1 rank and on the run's ranks; MUMPS on the
# same deck gives the direct reference (factorization + solve of that system,
# peak memory of the run), and hypre's MGR inside geoblock (&solver precon =
# 'mgr', GEOS's strategies, mgr_precon.f90) runs on the same distributed
# matrices in the same way as ours. Every one of them solves the exported
# system to rtol = 1e-8 (for the contact family, geoblock and MGR with
# &contact moving_rtol = 0: the exact Newton loop).
# Cases:
#   mandel N G : Mandel (input/mandel.nml, quarter model, N x N x N/10; 80 is
#                the seed's size), one step of dt = G (the seed's gamma)
#   contact N MIX : the 5-level contact block at N cells per side
#                (tests/decks/contact_block.nml), friction 80 (stick: its
#                Newton iteration) or 10 degrees (slip: its second one)
#   nine N ORDER : the nine-fracture injection case on N cells per side
#                (tests/decks/flow_nine.nml; 17: 4 m cells), the first slipping
#                step's second Newton iteration (step 4), pressure_block ORDER
#                ('eliminated': blocks t, p, u; 'schur': t, u, p)
#   poro N MIX : poromechanics with faults, the injection into a fault of
#                tests/decks/poro_faults_states.nml on N cells per side; MIX
#                'slip' (step 3, 4/12/0 at 8 cells) or 'open' (step 4, with
#                open elements), its second Newton iteration; blocks t, u, q,
#                pm, p (PETSc: the two pressures in one split, as ours)
# Usage: bench/run_bench_peers.sh [ranks] [cases, each "kind:N:arg" or "kind:N:arg:mumps"] [mumps: all|marked|no]
# (MUMPS runs on every case with 'all', on the cases marked ':mumps' with 'marked')
set -u
cd "$(dirname "$0")/.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
np=${1:-2}
cases=${2:-"mandel:40:1:mumps mandel:80:0.15 mandel:80:1:mumps mandel:80:100 contact:40:stick:mumps contact:40:slip:mumps nine:17:eliminated:mumps nine:17:schur poro:16:slip:mumps poro:16:open"}
with_mumps=${3:-marked}
PY=${PYTHON:-/usr/bin/python3}
out=build/bench/peers
mkdir -p "$out"
cp tests/decks/nine_fractures_rate.tab "$out/"
table=build/bench/peers.md
echo "| case | unknowns (blocks) | geoblock: its / set-up / solve / total [s] | PETSc fieldsplit, 1 rank: its / total [s] / peak MB (outer factorization) | PETSc fieldsplit, $np ranks: its / total [s] | geoblock / PETSc ($np ranks) | hypre MGR in geoblock: its / set-up / solve / total [s] | geoblock / MGR | MUMPS ($np ranks): total [s] / peak MB of a rank |" > "$table"
echo "|---|---|---|---|---|---|---|---|---|" >> "$table"

deck() {  # kind n arg solver name -> $out/name.nml; prints the export's step and Newton iteration
  local kind=$1 n=$2 arg=$3 solver=$4 name=$5
  case $kind in
    mandel)
      local nz=$((n / 10))
      sed -e "s#nx = 20, ny = 20, nz = 1#nx = $n, ny = $n, nz = $nz#" \
          -e "s#upper = 1.0, 1.0, 0.05#upper = 1.0, 1.0, $(echo "scale=6; $nz / $n" | bc)#" \
          -e "s#dt = 0.05, t_end = 200.0, dt_growth = 1.12, dt_max = 5.0#dt = $arg, t_end = $arg, undrained = .false.#" \
          -e "s#method = 'fgmres', precon = 'block', rtol = 1.0e-8#$solver, export_step = 1, export_newton = 1#" \
          -e "s#dir = 'out', prefix = 'mandel'#dir = '$out', prefix = '$name', fields = .false.#" \
          -e "s#history = 'mandel_plate.tab'#history = '$PWD/input/mandel_plate.tab'#" \
          input/mandel.nml > "$out/$name.nml" ;;
    contact)
      # stick: the one Newton iteration (the active set is right at once);
      # slip: the second, after the statuses changed
      local fric=80.0 newton=1
      [ "$arg" = slip ] && { fric=10.0; newton=2; }
      sed -e "s/nx = 12, ny = 12, nz = 12/nx = $n, ny = $n, nz = $n/" \
          -e "s/method = 'mumps'/$solver, export_step = 1, export_newton = $newton/" \
          -e "s/n_steps = 2/n_steps = 1/" -e "s/friction_angle = 10.0/friction_angle = $fric/" \
          -e "s#prefix = 'contact_block'#prefix = '$name', fields = .false.#" -e "s#dir = 'out'#dir = '$out'#" \
          tests/decks/contact_block.nml > "$out/$name.nml" ;;
    nine)
      sed -e "s#dir = 'out'#dir = '$out'#" -e "s#prefix = 'flow_nine'#prefix = '$name', fields = .false.#" \
          -e "s#nx = 17, ny = 17, nz = 17#nx = $n, ny = $n, nz = $n#" -e "s#t_end = 15.0#t_end = 10.0#" \
          -e "s#method = 'mumps'#$solver, export_step = 4, export_newton = 2#" \
          -e "s#initial_pressure = 4.0e6#initial_pressure = 4.0e6, pressure_block = '$arg'#" \
          tests/decks/flow_nine.nml > "$out/$name.nml" ;;
    poro)
      local step=3
      [ "$arg" = open ] && step=4
      sed -e "s#dir = '[^']*', prefix = 'states'#dir = '$out', prefix = '$name', fields = .false.#" \
          -e "s#nx = 8, ny = 8, nz = 8#nx = $n, ny = $n, nz = $n#" -e "s#t_end = 4.0#t_end = $step.0#" \
          -e "s#method = 'mumps'#$solver, export_step = $step, export_newton = 2#" \
          tests/decks/poro_faults_states.nml > "$out/$name.nml" ;;
  esac
  # the peers solve the exported system to rtol from x = 0: so do we (and
  # MGR), not to &contact moving_rtol, the inexact loop's looser tolerance
  # of an iteration that may still move the active set
  [ "$kind" = mandel ] && return
  if grep -q '^&contact' "$out/$name.nml"; then
    sed -i '/^&contact/a\  moving_rtol = 0.0' "$out/$name.nml"
  else
    printf '&contact\n  moving_rtol = 0.0\n/\n' >> "$out/$name.nml"
  fi
}

for c in $cases; do
  IFS=: read -r kind n arg mark <<< "$c"
  name=${kind}_${n}_${arg}
  restart=100
  [ "$kind" = nine ] && restart=300
  deck "$kind" "$n" "$arg" "method = 'fgmres', rtol = 1.0e-8, restart = $restart" "$name"
  echo "== $name"
  mpirun -np "$np" bin/geoblock "$out/$name.nml" > "$out/$name.stdout" 2>&1 < /dev/null
  line=$(grep -m1 '(exported): iterations' "$out/$name.log")
  if [ -z "$line" ]; then
    echo "| $name | | run failed or exported nothing, see $out/$name.stdout | | | | | | |" | tee -a "$table"
    continue
  fi
  its=$(sed -E 's/.*iterations ([0-9]+),.*/\1/' <<< "$line")
  su=$(sed -E 's/.*set-up ([0-9.]+) s.*/\1/' <<< "$line")
  so=$(sed -E 's/.*solve ([0-9.]+) s.*/\1/' <<< "$line")
  tot=$(awk -v a="$su" -v b="$so" 'BEGIN {printf "%.3f", a + b}')
  stem=$(ls "$out/${name}"_step*_newton*_K.mtx | head -1)
  stem=${stem%_K.mtx}
  blocks=$(sed -n 3p "${stem}_fields.mtx" | sed -E 's/.*: //')
  rows=$(sed -n 4p "${stem}_fields.mtx" | awk '{print $1}')
  # PETSc: the outer Schur factorization (full, upper, lower) that is the
  # fastest on 1 rank, then on the run's ranks
  p1="" best=""
  for ft in full upper lower; do
    r=$(PETSC_OPTIONS="-pc_fieldsplit_schur_fact_type $ft" $PY bench/peer_petsc.py --restart "$restart" \
          --ours-setup "$su" --ours-solve "$so" --ours-its "$its" "$stem" 2>&1)
    echo "   ($ft) $r"
    grep -q "NOT converged\|error" <<< "$r" && continue
    t=$(sed -E 's/.*total ([0-9.]+) s.*/\1/' <<< "$r")
    if [ -z "$best" ] || awk -v a="$t" -v b="$bt" 'BEGIN {exit !(a < b)}'; then best=$ft; bt=$t; p1=$r; fi
  done
  [ -z "$best" ] && { best=full; p1="NOT converged with any factorization"; }
  pn=$(PETSC_OPTIONS="-pc_fieldsplit_schur_fact_type $best" mpirun -np "$np" $PY bench/peer_petsc.py \
         --restart "$restart" --ours-setup "$su" --ours-solve "$so" "$stem" 2>&1)
  echo "   geoblock: $line"; echo "   $p1"; echo "   $pn"
  get() { sed -E "s/.*$1 ([0-9.]+).*/\\1/" <<< "$2"; }
  p1c="$(get iterations "$p1") / $(get total "$p1") / $(get 'peak memory' "$p1") ($best)"
  pnc="$(get iterations "$pn") / $(get total "$pn")"
  grep -q "NOT converged" <<< "$p1" && p1c="not converged: $p1c"
  grep -q "NOT converged" <<< "$pn" && pnc="not converged: $pnc"
  ratio=$(get 'ratio ours \/ petsc' "$pn")
  # hypre's MGR on the same deck and system
  deck "$kind" "$n" "$arg" "method = 'fgmres', rtol = 1.0e-8, restart = $restart, precon = 'mgr'" "${name}_mgr"
  # MGR's BoomerAMGs run hypre's own cycle, not geoblock's (amg_cycle.c):
  # on Biot they get Chebyshev, hypre's faster smoother there (as PETSc's)
  [ "$kind" = mandel ] && printf "&amg\n  relax_type = 'chebyshev'\n/\n" >> "$out/${name}_mgr.nml"
  mpirun -np "$np" bin/geoblock "$out/${name}_mgr.nml" > "$out/${name}_mgr.stdout" 2>&1 < /dev/null
  gl=$(grep -m1 '(exported): iterations' "$out/${name}_mgr.log")
  g="failed, see $out/${name}_mgr.stdout"; gr="-"
  if [ -n "$gl" ]; then
    gi=$(sed -E 's/.*iterations ([0-9]+),.*/\1/' <<< "$gl")
    gs=$(sed -E 's/.*set-up ([0-9.]+) s.*/\1/' <<< "$gl")
    go=$(sed -E 's/.*solve ([0-9.]+) s.*/\1/' <<< "$gl")
    gt=$(awk -v a="$gs" -v b="$go" 'BEGIN {printf "%.3f", a + b}')
    g="$gi / $gs / $go / $gt"
    gr=$(awk -v a="$tot" -v b="$gt" 'BEGIN {printf "%.2f", a / b}')
    echo "   mgr: $gl"
  fi
  m="not run"
  if [ "$with_mumps" = all ] || { [ "$with_mumps" = marked ] && [ "$mark" = mumps ]; }; then
    deck "$kind" "$n" "$arg" "method = 'mumps'" "${name}_mumps"
    /usr/bin/time -v mpirun -np "$np" bin/geoblock "$out/${name}_mumps.nml" > "$out/${name}_mumps.stdout" 2>&1 < /dev/null
    ml=$(grep -m1 '(exported): iterations' "$out/${name}_mumps.log")
    if [ -n "$ml" ]; then
      mt=$(awk -v a="$(sed -E 's/.*set-up ([0-9.]+) s.*/\1/' <<< "$ml")" -v b="$(sed -E 's/.*solve ([0-9.]+) s.*/\1/' <<< "$ml")" 'BEGIN {printf "%.3f", a + b}')
      mm=$(grep -m1 'Maximum resident set size' "$out/${name}_mumps.stdout" | awk '{print int($NF/1024)}')
      m="$mt / $mm"
    else
      m="failed, see $out/${name}_mumps.stdout"
    fi
  fi
  echo "| $name | $rows ($blocks) | $its / $su / $so / $tot | $p1c | $pnc | ${ratio:--} | $g | $gr | $m |" | tee -a "$table"
done
echo "table: $table"
