#!/usr/bin/env bash
# Checkpoint and restart (doc/running.md, "Restart"), on 1 and 2 ranks:
#  1. elasticity (4 load steps), Biot (Terzaghi, 6 growing time steps after
#     the undrained one, FGMRES + block preconditioner) and contact (5 load
#     steps; the fault pressure rises after the checkpoint, so that elements
#     go from stick to slip after it): a continuous run writes its checkpoint
#     at step k; a second run resumes from it in a tree that holds only what
#     the first run had written up to step k (plus a residual row of a later
#     step, as a run stopped past the checkpoint leaves). Every HDF5 dataset,
#     the XDMF index and the residual history must equal the continuous
#     run's bit for bit. Also fracture flow (5 time steps, injection that
#     takes the fracture from stick through slip to open; the statuses
#     change after the restart point).
#  2. stop signals: a Biot run of many steps gets SIGTERM (sent to its ranks,
#     as a batch system does) or SIGUSR1 (sent to mpirun, which forwards it);
#     it must stop after the step with a checkpoint, exit 0 and say so, and
#     resuming from that checkpoint must end with the continuous run's fields.
#  3. bad restart files: missing, not HDF5, another physics, another number
#     of ranks: exit status 2 and one "geoblock: error:" line naming it.
set -u
cd "$(dirname "$0")/../.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
PY=${PYTHON:-/usr/bin/python3}
out=build/test-out/restart
rm -rf "$out"; mkdir -p "$out"
out=$(cd "$out" && pwd)
pass=0; fail=0
ok() { echo "  ok    $1"; pass=$((pass + 1)); }
ko() { echo "  FAIL  $1"; fail=$((fail + 1)); }

# run NP DECK LOG: geoblock, stdout and stderr to LOG; the exit status
run() { timeout 300 mpirun --oversubscribe -np "$1" bin/geoblock "$2" > "$3" 2>&1 < /dev/null; }

# an attribute of a checkpoint file
attr() { "$PY" -c "import h5py, sys; print(h5py.File(sys.argv[1], 'r').attrs[sys.argv[2]])" "$1" "$2"; }

# ---- decks (DIR and the extra &run / &output lines are filled in by deck()) --
cat > "$out/elasticity.tpl" <<'DECK'
&run
  physics = 'elasticity' @RUN@
/
&mesh
  source = 'box', nx = 7, ny = 6, nz = 5, lower = 0, 0, 0, upper = 2.0, 1.5, 1.0, grading = 1.5, 1.0, 0.7
/
&material
  region = 'domain', young = 5.0e9, poisson = 0.28, body_force = 0, 0, -2.2e4
/
&boundary
  set = 'zmin', type = 'displacement', ux = 0, uy = 0, uz = 0
/
&boundary
  set = 'xmax', type = 'displacement', ux = 1.0e-4
/
&boundary
  set = 'zmax', type = 'traction', traction = 2.0e5, 0, -1.0e6
/
&time
  n_steps = 4
/
&solver
  method = 'fgmres', precon = 'boomeramg', rtol = 1.0e-8
/
&probe
  name = 'pt', x = 1.1, 0.3, y = 0.7, 1.5, z = 0.4, 1.0, fields = 'ux', 'uz', 'sxz'
/
&probe
  name = 'top', set = 'zmax', fields = 'uz', 'szz'
/
&output
  dir = '@DIR@', prefix = 'el' @OUT@
/
DECK
cat > "$out/biot.tpl" <<'DECK'
&run
  physics = 'biot' @RUN@
/
&mesh
  source = 'box', nx = 1, ny = 1, nz = 12, lower = 0.0, 0.0, 0.0, upper = 1.0, 1.0, 10.0
/
&material
  region = 'domain', young = 1.0e8, poisson = 0.25
  biot = 1.0, biot_modulus = 1.0e10, permeability = 1.0e-12, viscosity = 1.0e-3
/
&boundary
  set = 'zmin', type = 'displacement', ux = 0, uy = 0, uz = 0
/
&boundary
  set = 'xmin', type = 'displacement', ux = 0
/
&boundary
  set = 'xmax', type = 'displacement', ux = 0
/
&boundary
  set = 'ymin', type = 'displacement', uy = 0
/
&boundary
  set = 'ymax', type = 'displacement', uy = 0
/
&boundary
  set = 'zmax', type = 'traction', traction = 0, 0, -1.0e6
/
&boundary
  set = 'zmax', type = 'pressure', pressure = 0.0
/
&time
  @TIME@
/
&solver
  @SOLVER@
/
&probe
  name = 'mid', x = 0.5, y = 0.5, z = 5.0, fields = 'p', 'uz', 'szz'
/
&output
  dir = '@DIR@', prefix = 'biot' @OUT@
/
DECK
printf '0.0 0.0\n0.6 0.0\n1.0 1.0\n' > "$out/fault_pressure.tab"
cat > "$out/contact.tpl" <<DECK
&run
  physics = 'contact' @RUN@
/
&mesh
  source = 'box', nx = 8, ny = 8, nz = 8, lower = 0.0, 0.0, 0.0, upper = 1.0, 1.0, 1.0
/
&fault
  name = 'fault', normal_axis = 'z', position = 0.5, dip = 20.0, dip_axis = 'x'
  lower = 0.25, 0.25, 0.0, upper = 0.75, 0.75, 0.0, friction_angle = 10.0
  pressure = 9.0e6, pressure_history = '$out/fault_pressure.tab'
/
&material
  region = 'domain', young = 1.0e10, poisson = 0.25
/
&boundary
  set = 'zmin', type = 'displacement', ux = 0.0, uy = 0.0, uz = 0.0
/
&boundary
  set = 'zmax', type = 'traction', traction = 4.0e6, 0.0, -1.0e7
/
&time
  n_steps = 5
/
&solver
  method = 'fgmres', rtol = 1.0e-10
/
&output
  dir = '@DIR@', prefix = 'ct' @OUT@
/
DECK

cat > "$out/flow.tpl" <<DECK
&run
  physics = 'fracture_flow' @RUN@
/
&mesh
  source = 'box', nx = 8, ny = 8, nz = 8, lower = 0.0, 0.0, 0.0, upper = 1.0, 1.0, 1.0
/
&fault
  name = 'fault', normal_axis = 'z', position = 0.5, dip = 20.0, dip_axis = 'x'
  lower = 0.25, 0.25, 0.0, upper = 0.75, 0.75, 0.0, friction_angle = 10.0
/
&material
  region = 'domain', young = 1.0e10, poisson = 0.25
/
&boundary
  set = 'zmin', type = 'displacement', ux = 0.0, uy = 0.0, uz = 0.0
/
&boundary
  set = 'zmax', type = 'traction', traction = 4.0e6, 0.0, -1.0e7
/
&well
  name = 'inj', point = 0.5, 0.5, 0.5, rate = 3.2e-9
/
&time
  dt = 1.0, t_end = 5.0
/
&solver
  method = 'mumps'
/
&output
  dir = '@DIR@', prefix = 'ff' @OUT@
/
DECK

# deck TEMPLATE DIR RUN OUT [TIME SOLVER] > deck
deck() {
  sed -e "s#@DIR@#$2#" -e "s#@RUN@#$3#" -e "s#@OUT@#$4#" -e "s#@TIME@#${5:-}#" -e "s#@SOLVER@#${6:-}#" "$1"
}
biot_time="dt = 1.0, t_end = 20.0, dt_growth = 1.5"
biot_solver="method = 'fgmres', rtol = 1.0e-10"

# ---- 1. continuous run against a run resumed from its step-k checkpoint -----
# restart_case NAME NP TEMPLATE PREFIX K [TIME SOLVER]
restart_case() {
  local name=$1 np=$2 tpl=$3 p=$4 k=$5 time=${6:-} solver=${7:-}
  local a=$out/$name-np$np/continuous b=$out/$name-np$np/restarted
  local what="$name on $np rank(s), restart after step $k"
  mkdir -p "$a" "$b"
  deck "$tpl" "$a" "" ", checkpoint_every = $k" "$time" "$solver" > "$a.nml"
  if ! run "$np" "$a.nml" "$a.stdout"; then ko "$what: the continuous run fails, see $a.stdout"; return; fi
  local ck=$a/${p}_checkpoint.h5
  if [ ! -f "$ck" ] || [ "$(attr "$ck" step)" != "$k" ]; then ko "$what: no checkpoint of step $k in $a"; return; fi
  # what the first run had written up to step k: mesh, step files, history
  local n_out s f
  n_out=$(attr "$ck" n_outputs)
  cp "$a/${p}_mesh.h5" "$ck" "$b/"
  for ((s = 0; s < n_out; s++)); do
    f=$(printf '%s_%04d.h5' "$p" "$s"); cp "$a/$f" "$b/"
  done
  awk -F, -v k="$k" 'NR == 1 || $1 + 0 <= k' "$a/${p}_residuals.csv" > "$b/${p}_residuals.csv"
  echo "$((k + 1)),9.99e+99,1,0,1.0" >> "$b/${p}_residuals.csv"
  awk -F, -v k="$k" 'NR == 1 || $1 + 0 <= k' "$a/${p}_probes.csv" > "$b/${p}_probes.csv"
  echo "$((k + 1)),9.99e+99,1.0" >> "$b/${p}_probes.csv"
  deck "$tpl" "$b" ", restart = '$b/${p}_checkpoint.h5'" "" "$time" "$solver" > "$b.nml"
  if ! run "$np" "$b.nml" "$b.stdout"; then ko "$what: the restarted run fails, see $b.stdout"; return; fi
  grep -q "restart from '.*': step $k " "$b.stdout" || ko "$what: no restart line in $b.stdout"
  mv "$a/$p.log" "$a.log.txt"; mv "$b/$p.log" "$b.log.txt"
  local msg
  if msg=$("$PY" tools/compare_outputs.py "$a" "$b" --tol 0 2>&1) && ! grep -q "^only in" <<< "$msg"; then
    ok "$what: every HDF5 dataset bit for bit ($(tail -n 1 <<< "$msg"))"
  else
    ko "$what: outputs differ: $msg"
  fi
  if cmp -s "$a/$p.xdmf" "$b/$p.xdmf" && cmp -s "$a/${p}_residuals.csv" "$b/${p}_residuals.csv"; then
    ok "$what: XDMF index and residual history ($(($(wc -l < "$a/${p}_residuals.csv") - 1)) rows) identical"
  else
    ko "$what: XDMF or residual history differ ($a, $b)"
  fi
  if [ -f "$a/${p}_probes.csv" ] && cmp -s "$a/${p}_probes.csv" "$b/${p}_probes.csv"; then
    ok "$what: probe file ($(($(wc -l < "$a/${p}_probes.csv") - 1)) rows, $(head -1 "$a/${p}_probes.csv" | tr ',' '\n' | wc -l) columns) identical"
  else
    ko "$what: probe files differ or missing ($a, $b)"
  fi
  if [ -f "$a/${p}_fractures.xdmf" ] || [ -f "$b/${p}_fractures.xdmf" ]; then
    cmp -s "$a/${p}_fractures.xdmf" "$b/${p}_fractures.xdmf" && ok "$what: fractures XDMF identical" || \
      ko "$what: fractures XDMF differ ($a, $b)"
  fi
}

for np in 1 2; do
  restart_case elasticity "$np" "$out/elasticity.tpl" el 3
  restart_case biot "$np" "$out/biot.tpl" biot 4 "$biot_time" "$biot_solver"
  restart_case contact "$np" "$out/contact.tpl" ct 3
  # fracture flow: the statuses change after the checkpoint (step 3 -> 4,
  # 4/12/0 -> 0/12/4: elements open)
  restart_case flow "$np" "$out/flow.tpl" ff 3
  st=$(grep -E "^time step (3|4) " "$out/flow-np$np/continuous.stdout" | sed -E 's#.*stick/slip/open ([0-9/]+).*#\1#' | paste -sd' ')
  set -- $st
  if [ $# -eq 2 ] && [ "$1" != "$2" ]; then
    ok "flow on $np rank(s): statuses change after the restart point ($1 -> $2)"
  else
    ko "flow on $np rank(s): no status change after the restart point ($st)"
  fi
  # the flow run's checkpoint (MUMPS: blocks u, t, p) resumed with FGMRES and
  # the eliminated pressure (blocks t, p, u): the state is stored by field,
  # so the run goes on from the same state (results to the solver's tolerance;
  # FGMRES to 1e-11: 1e-12 is the floor of what it attains on these systems,
  # one of step 4's stagnated at 1.1e-12 on 1 rank, the step was cut and
  # took another path of statuses)
  a=$out/flow-np$np/continuous; c=$out/flow-np$np/solver_change
  mkdir -p "$c"; cp "$a/ff_mesh.h5" "$a/ff_checkpoint.h5" "$a"/ff_000[0-3].h5 "$c/" 2>/dev/null
  awk -F, 'NR == 1 || $1 + 0 <= 3' "$a/ff_residuals.csv" > "$c/ff_residuals.csv"
  awk -F, 'NR == 1 || $1 + 0 <= 3' "$a/ff_probes.csv" > "$c/ff_probes.csv"
  deck "$out/flow.tpl" "$c" ", restart = '$c/ff_checkpoint.h5'" "" | \
    sed "s#method = 'mumps'#method = 'fgmres', rtol = 1.0e-11#" > "$c.nml"
  if run "$np" "$c.nml" "$c.stdout"; then
    if msg=$("$PY" - "$a/ff_0005.h5" "$c/ff_0005.h5" <<'PY' 2>&1
import sys, h5py, numpy as np
a, b = h5py.File(sys.argv[1]), h5py.File(sys.argv[2])
worst = 0.0
def walk(name, obj):
    global worst
    if isinstance(obj, h5py.Dataset) and obj.dtype.kind == "f":
        x, y = obj[()], b[name][()]
        # cff (|t_T| - tau) is zero to round-off where every element slips or
        # is open: measured against the tractions' size
        ref = np.abs(a["fractures/normal_traction"][()]).max() if name.endswith("cff") else np.abs(x).max()
        worst = max(worst, float(np.abs(x - y).max() / max(ref, 1e-300)))
a.visititems(walk)
print(f"step 5 after a restart at step 3 with FGMRES ('eliminated') against MUMPS throughout: largest relative difference {worst:.1e}")
sys.exit(0 if worst < 1e-6 else 1)
PY
    ); then ok "flow on $np rank(s): $msg (1e-6)"; else ko "flow on $np rank(s), solver changed at the restart: $msg"; fi
  else
    ko "flow on $np rank(s): the restart with FGMRES fails, see $c.stdout"
  fi
  # the restart point must come before a status change for the test to mean something
  st=$(grep -E "^load step (3|5)/5" "$out/contact-np$np/continuous.stdout" | sed -E 's#.*stick/slip/open ([0-9/]+).*#\1#' | paste -sd' ')
  set -- $st
  if [ $# -eq 2 ] && [ "$1" != "$2" ]; then ok "contact on $np rank(s): statuses change after the checkpoint ($1 -> $2)"
  else ko "contact on $np rank(s): no status change after step 3 ($st)"; fi
done

# ---- 2. stop signals ---------------------------------------------------------
long_time="dt = 0.2, t_end = 120.0"
long_solver="method = 'mumps'"
c=$out/signal/continuous
mkdir -p "$c"
deck "$out/biot.tpl" "$c" "" ", every = 100" "$long_time" "$long_solver" > "$c.nml"
run 2 "$c.nml" "$c.stdout" || ko "signal: the continuous Biot run fails, see $c.stdout"
mv "$c/biot.log" "$c.log.txt"

# signal_case NAME SIGNAL TARGET(ranks|mpirun)
signal_case() {
  local name=$1 sig=$2 target=$3 d=$out/signal/$1
  mkdir -p "$d"
  deck "$out/biot.tpl" "$d" "" ", every = 100" "$long_time" "$long_solver" > "$d.nml"
  timeout 300 mpirun --oversubscribe -np 2 bin/geoblock "$d.nml" > "$d.stdout" 2>&1 < /dev/null &
  local pid=$! i
  for ((i = 0; i < 600; i++)); do
    grep -q "^step *5 " "$d.stdout" 2> /dev/null && break
    sleep 0.05
  done
  # $pid is timeout's; mpirun is its child, the ranks are mpirun's
  local victims
  victims=$(pgrep -P "$pid" -x mpirun)
  if [ "$target" = ranks ]; then victims=$(pgrep -P "$victims" -f geoblock); fi
  kill -s "$sig" $victims
  wait "$pid"
  local rc=$? what="$sig to the $target"
  local line
  line=$(grep "stopped by signal SIG$sig after step" "$d.stdout")
  if [ "$rc" -eq 0 ] && [ -n "$line" ] && [ -f "$d/biot_checkpoint.h5" ]; then
    ok "$what: exit 0, checkpoint, '${line:0:60}...'"
  else
    ko "$what: exit $rc, see $d.stdout"; return
  fi
  local step
  step=$(attr "$d/biot_checkpoint.h5" step)
  deck "$out/biot.tpl" "$d" ", restart = '$d/biot_checkpoint.h5'" ", every = 100" "$long_time" "$long_solver" > "$d-r.nml"
  mv "$d/biot.log" "$d.log.txt"
  if ! run 2 "$d-r.nml" "$d-r.stdout"; then ko "$what: the resumed run fails, see $d-r.stdout"; return; fi
  mv "$d/biot.log" "$d-r.log.txt"
  rm "$d/biot_checkpoint.h5"
  local msg
  if msg=$("$PY" tools/compare_outputs.py "$c" "$d" --tol 0 2>&1) && ! grep -q "^only in" <<< "$msg" \
     && cmp -s "$c/biot.xdmf" "$d/biot.xdmf" && cmp -s "$c/biot_residuals.csv" "$d/biot_residuals.csv"; then
    ok "$what: resumed after step $step, the outputs equal the continuous run's bit for bit ($(tail -n 1 <<< "$msg"))"
  else
    ko "$what: resumed after step $step, outputs differ: $msg"
  fi
}
signal_case term TERM ranks
signal_case usr1 USR1 mpirun

# ---- 3. bad restart files -------------------------------------------------------
# bad_case NAME NP DECK EXPECTED_TEXT
bad_case() {
  local log=$out/bad-$1.stdout
  run "$2" "$3" "$log"
  local rc=$? n
  n=$(grep -c "^geoblock: error:" "$log")
  if [ "$rc" -eq 2 ] && [ "$n" -eq 1 ] && grep "^geoblock: error:" "$log" | grep -q "$4"; then
    ok "bad restart ($1, $2 rank(s)): exit 2, $(grep '^geoblock: error:' "$log" | cut -c1-110)"
  else
    ko "bad restart ($1): exit $rc, $n error lines, see $log"
  fi
}
e2=$out/elasticity-np2/continuous/el_checkpoint.h5
echo "not an HDF5 file" > "$out/text.h5"
deck "$out/elasticity.tpl" "$out/bad" ", restart = '$out/none.h5'" "" > "$out/bad-missing.nml"
deck "$out/elasticity.tpl" "$out/bad" ", restart = '$out/text.h5'" "" > "$out/bad-text.nml"
deck "$out/biot.tpl" "$out/bad" ", restart = '$e2'" "" "$biot_time" "$biot_solver" > "$out/bad-physics.nml"
deck "$out/elasticity.tpl" "$out/bad" ", restart = '$e2'" "" > "$out/bad-ranks.nml"
bad_case missing 2 "$out/bad-missing.nml" "does not exist"
bad_case text 2 "$out/bad-text.nml" "is not an HDF5 file"
bad_case physics 2 "$out/bad-physics.nml" "written by physics = 'elasticity', this run is physics = 'biot'"
bad_case ranks 1 "$out/bad-ranks.nml" "written on 2 ranks, this run has 1"
deck "$out/elasticity.tpl" "$out/bad" "" ", checkpoint_every = -1" > "$out/bad-every.nml"
bad_case checkpoint_every 1 "$out/bad-every.nml" "variable checkpoint_every: must be 0"

echo "suite restart: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
