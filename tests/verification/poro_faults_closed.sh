#!/usr/bin/env bash
# physics = 'poromechanics_faults' against closed forms (issue 33,
# deliverable 3; MUMPS). tests/verification/check_poro_faults_closed.py
# states each check and its bound.
# 1. Mandel's problem cut by a glued (stick), hydraulically transparent
#    (exchange 'open') fault dipping 20 degrees across the specimen, so
#    that the flow crosses it (tests/decks/poro_faults_mandel.nml): the
#    pressure of every cell and the displacement of every node at every step
#    against biot's uncut run, within the fault's storage and compliance
#    bound; both runs against Mandel's closed form (2 % of p0, mandel.sh's
#    comparison).
# 2. A fracture well producing at a constant rate from a highly conductive
#    vertical fracture in a rigid reservoir (tests/decks/poro_faults_frac_well.nml):
#    the well's pressure against Gringarten, Ramey and Raghavan's (1974)
#    infinite-conductivity solution through linear and pseudo-radial flow
#    (3 %), every element of the fracture at the well's pressure (1 %).
# 3. A fault pressurized uniformly until it slips
#    (tests/decks/poro_faults_onset.nml): the pressure of every cell and element
#    against the closed form; no element slips before the time the effective
#    Coulomb limit predicts, all slip in the step that contains it.
set -u
cd "$(dirname "$0")/../.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
. tests/common/vreport.sh
. tests/common/suite.sh
PY=${PYTHON:-/usr/bin/python3}
CHECK=tests/verification/check_poro_faults_closed.py
out=build/test-out/poro_faults_closed
rm -rf "$out"; mkdir -p "$out"
# run NAME RANKS: bin/geoblock on $out/NAME.nml (tests/common/suite.sh deck), its screen in $out/NAME.log
run() { timeout 600 mpirun --oversubscribe -np "$2" bin/geoblock "$out/$1.nml" > "$out/$1.log" 2>&1 < /dev/null; }

# 1. Mandel with a glued, transparent fault, and biot's uncut run
$PY postproc/make_mandel_history.py "$out/mandel_plate.tab" 6e8 0.2 0.9 8e9 2e-14 1e-3 1 1 2e6 40 \
  || ko "make_mandel_history.py"
$PY tests/verification/make_mandel_fault_msh.py "$out/mandel_fault.msh" || ko "make_mandel_fault_msh.py"
deck mandel_fault tests/decks/poro_faults_mandel.nml
sed -e "s#physics = 'poromechanics_faults'#physics = 'biot'#" -e "/^&fault/,/^\//d" -e "/^&fracture_flow/,/^\//d" \
  -e "s#$out/mandel_fault#$out/mandel_biot#" "$out/mandel_fault.nml" > "$out/mandel_biot.nml"
if run mandel_fault 1; then ok "Mandel with the glued fault"; else ko "Mandel with the glued fault, see $out/mandel_fault.log"; fi
run mandel_biot 1 || ko "Mandel, biot's uncut run, see $out/mandel_biot.log"
r=$($PY $CHECK mandel "$out/mandel_fault" "$out/mandel_biot" mandel 2e6 2>&1); rc=$?
lines $rc "$r" "Mandel with a glued fault"

# 2. the fracture well against Gringarten, Ramey and Raghavan (1974), from
# early linear flow (t_D = 2e-3) to pseudo-radial flow (t_D = 10; the
# domain's edge, 30 x_f away, is not felt by then)
deck well tests/decks/poro_faults_frac_well.nml
if run well 1; then ok "fracture well run"; else ko "fracture well run, see $out/well.log"; fi
r=$($PY $CHECK gringarten "$out/well" well --td-min 2e-3 --td-max 10 --tol 0.03 2>&1); rc=$?
lines $rc "$r" "fracture well"

# 3. injection into a fault until it slips (2 ranks)
deck onset tests/decks/poro_faults_onset.nml
if run onset 2; then ok "injection into a fault run (2 ranks)"; else ko "injection into a fault run, see $out/onset.log"; fi
r=$($PY $CHECK onset "$out/onset" onset --tol 0.01 2>&1); rc=$?
lines $rc "$r" "injection until slip"

finish poro_faults_closed
