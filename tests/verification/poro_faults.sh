#!/usr/bin/env bash
# physics = 'poromechanics_faults' (issue 33, deliverable 1): the matrix's
# fluid with the fractures' (matrix_flow_component.f90), MUMPS.
# 1. A Terzaghi column (tests/decks/poro_faults_test.nml: 2 x 2 x 60 cells,
#    top impermeable) cut at z = H/3 by a fracture held at zero pressure:
#    each part follows single-drained Terzaghi consolidation of its own
#    height (every cell within 1 % of p0 at t = 4, 12, 40 s), the fracture's
#    inflow from both sides within 1 % of the analytical leak-off, the
#    mass balance at round-off in every step; 1 vs 2 ranks. The same
#    fracture balancing its own fluid (open exchange, the top drained) is
#    transparent: the column follows biot's uncut one.
# 2. A sealing fault at mid-height (top drained, the fracture held at zero
#    pressure): no flux through it, the lower part keeps its undrained
#    pressure p0 (the jump across the fault kept), the upper part follows
#    Terzaghi of its own height, mass balance at round-off.
# 3. A barrier of large transmissibility behaves like the open exchange.
# 4. Without faults the composition gives biot's Terzaghi (1e-10).
# 5. FGMRES with the block preconditioner against MUMPS (1e-6) and 1 vs 2
#    vs 3 ranks (1e-8) on an injection into a fault in a permeable matrix
#    that goes from stick through slip to open; its outputs checked against
#    each other (pressures, leak-off, tractions, CFF, the probes' per-fault
#    leak-off and slip).
set -u
cd "$(dirname "$0")/../.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
. tests/common/vreport.sh
PY=${PYTHON:-/usr/bin/python3}
out=build/test-out/poro_faults
rm -rf "$out"; mkdir -p "$out"
pass=0; fail=0
ok() { echo "  ok    $1"; pass=$((pass + 1)); }
ko() { echo "  FAIL  $1"; fail=$((fail + 1)); }
deck() {  # name, source deck, sed expressions...
  local name=$1 src=$2; shift 2
  sed -e "s#dir = '[^']*'#dir = '$out/$name'#" "$@" "$src" > "$out/$name.nml"
}
run() {  # name, ranks
  timeout 600 mpirun --oversubscribe -np "$2" bin/geoblock "$out/$1.nml" > "$out/$1.log" 2>&1 < /dev/null
}
worst_balance() {  # name: the largest mass balance of the step lines
  grep '^time step' "$out/$1.log" | sed -E 's/.*mass balance +([0-9.E+-]+).*/\1/' | sort -g | tail -1
}
balance() {  # name, case
  local w
  w=$(worst_balance "$1")
  if [ -n "$w" ]; then vcheck "$2" "mass balance, worst step (relative)" "$w" 1e-10; else ko "$2: no mass balance"; fi
}

# 1. the drained fracture
src=tests/decks/poro_faults_test.nml
deck cut1 $src
if run cut1 1; then ok "cut column run (1 rank)"; else ko "cut column run, see $out/cut1.log"; fi
while read -r line; do
  case "$line" in *FAIL*|*Traceback*|*Error:*) ko "$line" ;; *) ok "$line" ;; esac
done < <($PY tests/verification/check_poro_faults.py "$out/cut1" cut --cut 3.3333333333 --times 4,12,40 2>&1)
balance cut1 "Terzaghi column cut by a drained fracture, 60 cells"
deck cut2 $src
run cut2 2 || ko "cut column run on 2 ranks, see $out/cut2.log"
if r=$($PY tests/invariance/compare_runs.py "$out/cut1" "$out/cut2" cut 1e-10 pressure displacement 2>&1); then
  ok "1 vs 2 ranks: $(echo "$r" | tail -2 | tr '\n' ' ')"
else
  ko "1 vs 2 ranks: $(echo "$r" | tr '\n' ' ')"
fi

# 1b. the fracture balancing its own fluid (no &fracture_pressure), the
# exchange open, the top drained: a closed fracture of tiny storage passes
# the lower part's fluid to the upper part, so the column follows biot's
# uncut Terzaghi column on the same cells (what differs: the fracture's
# storage and its pressure stabilization; measured 2.5e-5 p0 at 40 s)
deck pass $src -e "s#nz = 60#nz = 30#" -e "/^&fracture_pressure/,/^\//d" \
  -e "s#dt = 0.02, t_end = 40.0, dt_growth = 1.05, dt_max = 0.25#dt = 0.25, t_end = 40.0, dt_growth = 1.1, dt_max = 2.0#"
printf "&boundary\n  set = 'zmax', type = 'pressure', pressure = 0.0\n/\n" >> "$out/pass.nml"
sed -e "s#physics = 'poromechanics_faults'#physics = 'biot'#" -e "/^&fault/,/^\//d" -e "s#$out/pass#$out/pass_biot#" \
  "$out/pass.nml" > "$out/pass_biot.nml"
run pass 1 || ko "transparent fracture run, see $out/pass.log"
run pass_biot 1 || ko "biot run of the uncut column, see $out/pass_biot.log"
r=$($PY - "$out" <<'PY'
import sys
sys.path.insert(0, "postproc"); sys.path.insert(0, "tests/common")
import numpy as np
from geoblock_h5 import Run
from vreport import record
a, b = Run(f"{sys.argv[1]}/pass", "cut"), Run(f"{sys.argv[1]}/pass_biot", "cut")
oa = np.lexsort(a.cell_centres().T[::-1].round(9))
ob = np.lexsort(b.cell_centres().T[::-1].round(9))
p0 = b.field("pressure", 0).max()
d = max(np.abs(a.field("pressure", i)[oa] - b.field("pressure", i)[ob]).max() / p0 for i in range(len(b.steps)))
good = len(a.steps) == len(b.steps) and record("Terzaghi column, 30 cells, an open fracture at H/3 balancing its fluid",
                                               "pressure against biot's uncut column, every step (/ p0)", d, 1e-4)
print(f"open fracture balancing its own fluid vs biot's uncut column: largest cell pressure difference {d:.2e} p0 "
      f"over {len(a.steps)} steps (tol 1e-4) {'ok' if good else 'FAIL'}")
PY
)
case "$r" in *ok) ok "$r" ;; *) ko "$r" ;; esac
balance pass "Terzaghi column, 30 cells, an open fracture at H/3 balancing its fluid"

# 2. a sealing fault at mid-height, the top drained
deck seal $src -e "s#nz = 60#nz = 20#" -e "s#position = 3.3333333333#position = 5.0, exchange = 'sealing'#" \
  -e "s#dt = 0.02, t_end = 40.0, dt_growth = 1.05, dt_max = 0.25#dt = 0.05, t_end = 60.0, dt_growth = 1.1, dt_max = 1.0#" \
  -e "s#prefix = 'cut'#prefix = 'seal'#"
printf "&boundary\n  set = 'zmax', type = 'pressure', pressure = 0.0\n/\n" >> "$out/seal.nml"
if run seal 1; then ok "sealing fault run"; else ko "sealing fault run, see $out/seal.log"; fi
r=$($PY - "$out/seal" <<'PY'
import sys, os
sys.path.insert(0, "postproc"); sys.path.insert(0, "tests/common")
import h5py
import numpy as np
from analytical import PoroParams, Terzaghi
from geoblock_h5 import Run
from vreport import record
run = Run(sys.argv[1], "seal")
z = run.cell_centres()[:, 2]
low = z < 5.0
tz = Terzaghi(PoroParams(E=1e8, nu=0.25, b=1.0, M=1e10, k=1e-12, mu=1e-3), 5.0, 1e6)
flux = held = 0.0
for i in range(len(run.steps)):
    with h5py.File(run.steps[i], "r") as f:
        flux = max(flux, float(np.max(np.abs(f["fractures/leakoff"]))))
    held = max(held, float(np.max(np.abs(run.field("pressure", i)[low] - tz.p0))) / tz.p0)
t = run.times()[-1]
p = run.field("pressure", -1)
g, w = np.polynomial.legendre.leggauss(8)
h = 10.0 / len(np.unique(np.round(z, 9)))
ex = sum(wi * tz.pressure(np.clip(z[~low] - 5.0 + 0.5 * h * gi, 0.0, 5.0), t) for gi, wi in zip(g, w)) / 2.0
l2 = np.sqrt(np.sum((p[~low] - ex) ** 2) / np.sum(ex ** 2))
jump = p[low].min() - p[~low].max()
case = "Terzaghi column with a sealing fault at mid-height, 20 cells"
good = [record(case, "flux through the fault, every step [m3/s]", flux, 0.0),
        record(case, "lower part's pressure - p0, every step (/ p0)", held, 1e-10),
        record(case, f"upper part at t = {t:.3g} s (pressure relative L2 error)", l2, 0.01)]
print(f"flux through the sealing fault, largest over the steps {flux:.1e} m3/s (must be 0) "
      f"{'ok' if good[0] else 'FAIL'}")
print(f"lower part held at p0 = {tz.p0:.6e} Pa: largest |p - p0| / p0 over the steps {held:.2e} (tol 1e-10) "
      f"{'ok' if good[1] else 'FAIL'}")
print(f"upper part, T = {tz.time_factor(t):.3f}: pressure relative L2 error {l2:.2e} (tol 0.01) "
      f"{'ok' if good[2] else 'FAIL'}; the jump across the fault at the last step {jump / tz.p0:.3f} p0")
sys.exit(0 if all(good) else 1)
PY
)
rc=$?
while read -r line; do
  case "$line" in *FAIL*|*Traceback*|*Error:*) ko "$line" ;; *) ok "$line" ;; esac
done <<< "$r"
[ $rc -eq 0 ] || ko "sealing fault checks (exit $rc)"
balance seal "Terzaghi column with a sealing fault at mid-height, 20 cells"

# 3. a barrier of large transmissibility (its resistance 1/lambda negligible)
# against the open exchange, on the first seconds of case 1
short="s#dt = 0.02, t_end = 40.0, dt_growth = 1.05, dt_max = 0.25#dt = 0.02, t_end = 2.0, dt_growth = 1.05, dt_max = 0.25#"
deck open $src -e "$short" -e "s#nz = 60#nz = 30#"
deck barrier $src -e "$short" -e "s#nz = 60#nz = 30#" \
  -e "s#position = 3.3333333333#position = 3.3333333333, exchange = 'barrier', exchange_transmissibility = 1.0e3#"
run open 1 || ko "open exchange run, see $out/open.log"
run barrier 1 || ko "barrier run, see $out/barrier.log"
if r=$($PY tests/invariance/compare_runs.py "$out/open" "$out/barrier" cut 1e-8 pressure displacement 2>&1); then
  ok "barrier, lambda = 1e3 m/(Pa s), vs open: $(echo "$r" | tail -2 | tr '\n' ' ')"
else
  ko "barrier vs open: $(echo "$r" | tr '\n' ' ')"
fi
deck weak $src -e "$short" -e "s#nz = 60#nz = 30#" \
  -e "s#position = 3.3333333333#position = 3.3333333333, exchange = 'barrier', exchange_transmissibility = 1.0e-12#"
run weak 1 || ko "weak barrier run, see $out/weak.log"
r=$($PY - "$out" <<'PY'
import sys
sys.path.insert(0, "postproc")
import h5py
import numpy as np
from geoblock_h5 import Run
lo = {}
for name in ("open", "weak"):
    r = Run(f"{sys.argv[1]}/{name}", "cut")
    with h5py.File(r.steps[-1], "r") as f:
        lo[name] = float(np.sum(f["fractures/leakoff"]))
    z = r.cell_centres()[:, 2]
    p = r.field("pressure", -1)
    near = p[np.abs(z - 10.0 / 3.0) < 0.2].mean()
    lo[name + "_p"] = near
# a weak barrier: the leak-off is lambda |f| (p - p_f) summed over both sides' faces
# (4 + 4 faces of 0.25 m2), with p the faces' pressure, near that of the cells at the fault
est = 1.0e-12 * 2 * 1.0 * lo["weak_p"]
rel = abs(lo["weak"] - est) / est
print(f"weak barrier (lambda 1e-12 m/(Pa s)): leak-off {lo['weak']:.4e} m3/s, lambda A_both (p at the fault) "
      f"{est:.4e} (relative {rel:.2e}, tol 0.01); open: {lo['open']:.4e} m3/s "
      f"{'ok' if rel <= 0.01 and lo['weak'] < lo['open'] else 'FAIL'}")
PY
)
case "$r" in *ok) ok "$r" ;; *) ko "$r" ;; esac

# 4. no fault: biot's Terzaghi
for phys in biot poromechanics_faults; do
  sed -e "s#dir = '[^']*'#dir = '$out/nofault_$phys'#" -e "s#physics = 'biot'#physics = '$phys'#" \
    -e "s#nz = 40#nz = 20#" -e "s#t_end = 200.0#t_end = 20.0#" tests/decks/terzaghi_test.nml > "$out/nofault_$phys.nml"
  run nofault_$phys 1 || ko "no-fault run ($phys), see $out/nofault_$phys.log"
done
if r=$($PY tests/invariance/compare_runs.py "$out/nofault_biot" "$out/nofault_poromechanics_faults" terzaghi 1e-10 \
       pressure displacement 2>&1); then
  ok "no fault, poromechanics_faults vs biot: $(echo "$r" | tail -2 | tr '\n' ' ')"
else
  ko "no fault, poromechanics_faults vs biot: $(echo "$r" | tr '\n' ' ')"
fi

# 5. the block preconditioner (poro_faults_precon.f90): injection into a
# fault in a permeable matrix until it slips and opens
# (tests/decks/poro_faults_states.nml), FGMRES against MUMPS (1e-6, every
# field at every step, relative to its largest magnitude), and 1 vs 2 vs 3
# ranks (1e-8)
src=tests/decks/poro_faults_states.nml
deck states_mumps $src
fgm="s#method = 'mumps'#method = 'fgmres', rtol = 1.0e-10#"
if run states_mumps 1; then
  st=$(grep -E "^time step" "$out/states_mumps.log" | sed -E 's#.*stick/slip/open ([0-9/]+).*#\1#' | paste -sd' ')
  if grep -q "^[1-9][0-9]*/[1-9][0-9]*/0" <<< "$st" && grep -qE "(^| )[1-9][0-9]*/[1-9][0-9]*/[1-9][0-9]*$" <<< "$st"; then
    ok "injection into a fault in a permeable matrix: stick, slip and open met: $st"
  else
    ko "injection into a fault in a permeable matrix: not every status met: $st"
  fi
else
  ko "injection run (MUMPS), see $out/states_mumps.log"
fi
for np in 1 2 3; do
  deck states_fgmres$np $src -e "$fgm"
  run states_fgmres$np $np || ko "injection run (FGMRES, $np ranks), see $out/states_fgmres$np.log"
done
its=$($PY -c "import csv, sys; print(max(int(r['iteration']) for r in csv.DictReader(open(sys.argv[1]))))" \
  "$out/states_fgmres1/states_residuals.csv" 2>&1)
check() {  # label, command...
  local label=$1 r; shift
  if r=$("$@" 2>&1); then ok "$label: $(tail -1 <<< "$r")"; else ko "$label: $(tr '\n' ' ' <<< "$r")"; fi
}
check "FGMRES + the block preconditioner vs MUMPS (largest count $its)" $PY tests/verification/check_poro_faults_same.py \
  "$out/states_mumps/states" "$out/states_fgmres1/states" 1e-6 "injection into a fault, FGMRES vs MUMPS"
# the outputs against each other (check_poro_faults_outputs.py): the
# datasets of both grids, the effective normal traction and the CFF
# recomputed from the total traction and the fracture pressure, the probe
# file's per-fault leak-off and slip from the elements
while read -r line; do
  case "$line" in *FAIL*|*Traceback*|*rror:*) ko "outputs: $line" ;; *) ok "outputs: $line" ;; esac
done < <($PY tests/verification/check_poro_faults_outputs.py "$out/states_mumps" states 2>&1)
for np in 2 3; do
  check "FGMRES, 1 vs $np ranks" $PY tests/verification/check_poro_faults_same.py "$out/states_fgmres1/states" \
    "$out/states_fgmres$np/states" 1e-8 "injection into a fault, FGMRES, 1 vs $np ranks"
done

echo "suite poro_faults: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
