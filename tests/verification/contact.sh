#!/usr/bin/env bash
# Frictional contact (physics = 'contact') against analytical solutions:
#  - Sneddon's pressurized crack (input/sneddon.nml): opening within 3 % over
#    every element, tips included, and first-order convergence over three core
#    refinements;
#  - the inclined crack under compression of Phan et al. (input/single_fracture.nml):
#    slip within 5 % (L2 over every element), t_N and |t_T| of every element,
#    tips included, within 1 %; 1 vs 2 ranks to 1e-8; a refinement study with
#    other parameters (30, 60, 120 elements): every element's tractions within
#    1 % at every level, all slipping, slip converging at order >= 0.8;
#  - a straight slipping crack whose Jacobian MUMPS found singular unscaled;
#  - a warning naming a fracture whose tips sit on sheared cells;
#  - a fault in stick under a homogeneous stress: the intact solution exactly;
#  - a partly slipping fracture with tips in a block: 1 vs 2 ranks to 1e-8
#    with the fracture shared by both ranks; the three block preconditioners
#    (FGMRES) give MUMPS's solution; its <prefix>_fractures.xdmf read by meshio;
#  - the face-bubble space (&contact space = 'bubble', a pure saddle point):
#    Sneddon and the inclined crack with the same tolerances, 1 vs 2 ranks,
#    the stick fault's intact solution, the partly slipping fracture on 1 and
#    2 ranks and with FGMRES (augmented preconditioner) against MUMPS.
set -u
cd "$(dirname "$0")/../.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
PY=${PYTHON:-/usr/bin/python3}
out=build/test-out/contact
rm -rf "$out"; mkdir -p "$out"
pass=0; fail=0
ok() { echo "  ok    $1"; pass=$((pass + 1)); }
ko() { echo "  FAIL  $1"; fail=$((fail + 1)); }
. tests/common/vreport.sh
verdict() { awk -v e="$1" -v t="$2" 'BEGIN {print (e + 0 <= t + 0) ? "pass" : "FAIL"}'; }
vorders() {  # case, quantity, minimum order, errors on meshes halving h: report rows
  local c=$1 q=$2 m=$3 prev="" o r k=0; shift 3
  for e in "$@"; do
    k=$((k + 1)); o=""; r=pass
    if [ -n "$prev" ]; then
      o=$(awk -v a="$prev" -v b="$e" 'BEGIN {printf "%.2f", log(a / b) / log(2)}')
      awk -v o="$o" -v m="$m" 'BEGIN {exit !(o >= m)}' || r=FAIL
    fi
    vreport "$c, level $k" "$q" "$e" "${prev:+order >= $m}" "$o" "$r"
    prev=$e
  done
}
deck() {  # name, source deck, sed expressions
  local name=$1 src=$2; shift 2
  sed -e "s#dir = 'out'#dir = '$out'#" -e "s#prefix = '[a-z_]*'#prefix = '$name'#" "$@" "$src" > "$out/$name.nml"
}
run() {  # name, ranks
  if timeout 600 mpirun --oversubscribe -np "$2" bin/geoblock "$out/$1.nml" > "$out/$1.stdout" 2>&1 < /dev/null; then
    return 0
  fi
  ko "run $1 on $2 rank(s), see $out/$1.log"
  return 1
}
space() {  # name, space: a deck of the face-bubble space gets its &contact group
  [ "$2" = stabilized ] || printf "&contact\n  space = '%s'\n/\n" "$2" >> "$out/$1.nml"
}
lin() {  # run -> FGMRES iterations of all its load steps
  grep '^load step' "$out/$1.log" | sed -E 's/.*linear its +([0-9]+).*/\1/' | awk '{s += $1} END {print s + 0}'
}
newtons() {  # run -> Newton iterations of its load steps, as a list
  grep '^load step' "$out/$1.log" | sed -E 's/.*newton +([0-9]+).*/\1/' | tr '\n' ' ' | sed 's/ $//'
}
fewer() {  # run, reference run, what: ok when run took fewer FGMRES iterations than the reference
  local a b
  a=$(lin "$1"); b=$(lin "$2")
  if [ "$a" -gt 0 ] && [ "$a" -lt "$b" ]; then ok "$3 takes fewer FGMRES iterations: $a < $b"
  else ko "$3: $a FGMRES iterations, against $b for $2"; fi
}
stronger() {  # name, reference run, MUMPS run, label, deck groups: the block case with
  # FGMRES and the groups (a stronger S* solve) must give MUMPS's answer to 1e-6
  # in fewer FGMRES iterations than the reference
  deck "$1" tests/decks/contact_block.nml -e "s#method = 'mumps'#method = 'fgmres', rtol = 1.0e-10#"
  printf "%b" "$5" >> "$out/$1.nml"
  if run "$1" 2; then
    check "$4 vs MUMPS (1e-6)" $PY tests/verification/check_contact.py same "$out/$3" "$out/$1" 1e-6
    fewer "$1" "$2" "$4"
  fi
}
check() {  # label, command...
  local label=$1 r; shift
  if r=$("$@" 2>&1); then ok "$label: $(echo "$r" | grep -v '^figure' | tr '\n' ' ')"; else ko "$label: $(echo "$r" | tr '\n' ' ')"; fi
}
error_of() {  # run, case, quantity
  $PY postproc/plot_fracture.py "$out/$1" --case "$2" --png "$out/$1.png" | awk -v q="$3" '$1 == "error" && $2 == q {print $3}'
}

# Sneddon, both spaces
for sp in stabilized bubble; do
  sfx=${sp#stabilized}; s=sneddon${sfx:+_$sfx}
  deck "$s" input/sneddon.nml
  space "$s" "$sp"
  if run "$s" 2; then
    check "Sneddon opening, every element (2 ranks, tol 3%, space $sp)" $PY postproc/plot_fracture.py \
      "$out/$s" --case sneddon --check 0.03 --png "$out/$s.png"
    r=$(error_of "$s" sneddon opening)
    vreport "Sneddon crack, h = b/20, space $sp" "opening (relative L2, every element)" "$r" 0.03 "" "$(verdict "$r" 0.03)"
  fi
done
e=()
for lv in "24 6 80 60" "48 10 110 80" "96 20 180 130"; do
  set -- $lv
  deck "sneddon_$1" input/sneddon.nml -e "s#nx = 110, ny = 80#nx = $3, ny = $4#" -e "s#core_n = 48, 10#core_n = $1, $2#"
  run "sneddon_$1" 2 && e+=("$(error_of "sneddon_$1" sneddon opening)")
done
if [ ${#e[@]} -eq 3 ]; then
  check "Sneddon convergence (order >= 0.8)" $PY tests/verification/check_contact.py orders "${e[@]}" 0.8
  vorders "Sneddon crack, h = b/10, b/20, b/40" "opening (relative L2, every element)" 0.8 "${e[@]}"
fi

# Phan et al.: inclined crack, all slipping; every element, tips included
# (the tip elements' t_N fell to 0.31, 0.09, 0 of the exact value on 30, 60,
# 120 elements before the box generator squared the cells up at dipped faults)
phan_check() {  # label, run, slip tol (L2), traction tol (every element)
  local r
  r=$($PY postproc/plot_fracture.py "$out/$2" --case phan --png "$out/$2.png" 2>&1)
  if awk -v s="$3" -v t="$4" '
      /^elements/ {split($4, c, "/"); allslip = (c[1] == 0 && c[3] == 0)}
      $1 == "error" && $2 == "slip" {okslip = ($3 <= s)}
      $1 == "maxerror" {n++; if ($3 <= t) okt++}
      END {exit !(allslip && okslip && n == 2 && okt == 2)}' <<< "$r"; then
    ok "$1: $(echo "$r" | grep -v '^figure' | tr '\n' ' ')"
  else
    ko "$1: $(echo "$r" | tr '\n' ' ')"
  fi
}
for sp in stabilized bubble; do
  sfx=${sp#stabilized}; s=phan${sfx:+_$sfx}
  deck "${s}1" input/single_fracture.nml
  deck "${s}2" input/single_fracture.nml
  space "${s}1" "$sp"
  space "${s}2" "$sp"
  if run "${s}1" 1; then
    phan_check "inclined crack, slip 5 %, every element's t_N, |t_T| 1 % (1 rank, space $sp)" "${s}1" 0.05 0.01
    r=$(error_of "${s}1" phan slip)
    vreport "inclined crack (Phan et al.), 38 elements, space $sp" "slip (relative L2, every element)" "$r" 0.05 "" \
      "$(verdict "$r" 0.05)"
  fi
  if run "${s}2" 2; then
    phan_check "inclined crack (2 ranks, space $sp)" "${s}2" 0.05 0.01
    check "inclined crack, 1 vs 2 ranks (1e-8, space $sp)" $PY tests/verification/check_contact.py same "$out/${s}1" \
      "$out/${s}2" 1e-8
  fi
done
# refinement with other parameters: psi = 30 degrees, friction 20 degrees,
# E = 30 GPa, nu = 0.3, sigma = 20 MPa (b = 1 m: the core spans b cos(psi))
e=()
for lv in "30 10" "60 20" "120 42"; do
  set -- $lv
  deck "phan_$1" input/single_fracture.nml -e "s#nx = 72, ny = 98#nx = $((60 + $2)), ny = $((60 + $1))#" \
    -e "s#core_n = 12, 38#core_n = $2, $1#" -e "s#0.9396926#0.8660254#g" -e "s#dip = 20.0#dip = 30.0#" \
    -e "s#friction_angle = 30.0#friction_angle = 20.0#" -e "s#young = 1.0e10#young = 3.0e10#" \
    -e "s#poisson = 0.25#poisson = 0.3#" -e "s#traction = 0.0, -1.0e7, 0.0#traction = 0.0, -2.0e7, 0.0#"
  if run "phan_$1" 2; then
    phan_check "inclined crack, psi 30, $1 elements: every element's t_N, |t_T| within 1 %" "phan_$1" 1.0 0.01
    e+=("$(error_of "phan_$1" phan slip)")
    r=$($PY postproc/plot_fracture.py "$out/phan_$1" --case phan --png "$out/phan_$1.png" | \
        awk '$1 == "maxerror" && $3 > m {m = $3} END {print m + 0}')
    vreport "inclined crack (psi 30), $1 elements" "t_N, |t_T| (largest relative error of an element)" "$r" 0.01 "" \
      "$(verdict "$r" 0.01)"
  fi
done
if [ ${#e[@]} -eq 3 ]; then
  check "inclined crack slip convergence, every element (order >= 0.8)" $PY tests/verification/check_contact.py \
    orders "${e[@]}" 0.8
  vorders "inclined crack (psi 30), 30, 60, 120 elements" "slip (relative L2, every element)" 0.8 "${e[@]}"
fi

# skewed tips are named: a second fault normal to the dip axis keeps the
# inclined crack's cells sheared (no squaring up), and the log says so
deck skew input/single_fracture.nml
printf "&fault\n  name = 'other'\n  normal_axis = 'y'\n  position = 15.0\n  lower = 10.0, 0.0, -1.0\n  upper = 15.0, 0.0, 1.0\n/\n" \
  >> "$out/skew.nml"
if run skew 2; then
  grep -q "warning: fault 'crack': the cells at its tips cross it at up to 20 degrees" "$out/skew.stdout" && \
    ! grep -q "cells at its tips" "$out/phan2.stdout" && ok "sheared cells at the tips are named (20 degrees), squared-up ones are not" \
    || ko "tip skew warning: $(grep warning "$out/skew.stdout")"
fi

# a Jacobian MUMPS called numerically singular before the scaled factorization
deck straight tests/decks/contact_straight_crack.nml
if run straight 1; then
  r=$($PY postproc/plot_fracture.py "$out/straight" --png "$out/straight.png" | head -1)
  [ "$r" = "elements 60  stick/slip/open 0/60/0" ] && ok "straight crack, MUMPS on 1 rank (D A D): $r" || \
    ko "straight crack, MUMPS on 1 rank: $r"
fi
# without the stabilization: the Q1-P0 pair is warned of, and a traction
# whose jump the boundary conditions fix (this slab's z tractions: uz = 0
# on both faces) is refused before the first step, on 1 and 2 ranks alike
w="warning: contact: stabilization = 'none' on space = 'stabilized': Q1 displacements with piecewise-constant"
e="error: fault 'crack': 60 traction component(s) act on a jump that the displacement conditions fix on both sides"
deck straight_none tests/decks/contact_straight_crack.nml
printf "&contact\n  stabilization = 'none'\n/\n" >> "$out/straight_none.nml"
for np in 1 2; do
  timeout 600 mpirun --oversubscribe -np $np bin/geoblock "$out/straight_none.nml" > "$out/straight_none$np.stdout" \
    2>&1 < /dev/null
  rc=$?
  [ $rc -eq 2 ] && grep -q "$e" "$out/straight_none$np.stdout" && ! grep -q "^load step" "$out/straight_none$np.stdout" \
    && ok "a traction on a jump fixed on both sides, unstabilized: refused before the first step ($np rank(s))" || \
    ko "unstabilized slab ($np rank(s)): exit $rc, $(grep -m1 error "$out/straight_none$np.stdout")"
done
deck stick_none tests/decks/contact_stick.nml
printf "&contact\n  stabilization = 'none'\n/\n" >> "$out/stick_none.nml"
if run stick_none 2; then
  grep -q "$w" "$out/stick_none.stdout" && ! grep -q "$w" "$out/straight.stdout" && \
    ok "stabilization = 'none' on the Q1-P0 space is warned of, the default is not" || \
    ko "unstabilized space warning: $(grep -c warning "$out/stick_none.stdout") warning line(s)"
  check "stick fault = intact solution, unstabilized (MUMPS, 2 ranks)" $PY tests/verification/check_contact.py stick \
    "$out/stick_none"
fi

# stick = intact
deck stick tests/decks/contact_stick.nml
run stick 2 && check "stick fault = intact solution (MUMPS, 2 ranks)" $PY tests/verification/check_contact.py stick "$out/stick"
deck stick_it tests/decks/contact_stick.nml -e "s#method = 'mumps'#method = 'fgmres', rtol = 1.0e-12#"
run stick_it 2 && check "stick fault = intact solution (FGMRES reordered, 2 ranks)" $PY \
  tests/verification/check_contact.py stick "$out/stick_it"

# partly slipping fracture: block preconditioners vs MUMPS
deck block_mumps tests/decks/contact_block.nml
deck block_mumps1 tests/decks/contact_block.nml
if run block_mumps 2 && run block_mumps1 1; then
  check "the fracture crosses the partition" $PY tests/verification/check_contact.py ranks "$out/block_mumps" 2
  check "block_mumps_fractures.xdmf read by meshio, every step = HDF5; legend, CFF, slip frame" $PY \
    tests/verification/check_contact.py meshio "$out/block_mumps" 10 0
  grep -q 'AttributeType="Tensor6"' "$out/block_mumps.xdmf" && ! grep -q 'fractures' "$out/block_mumps.xdmf" && \
    ok "the main XDMF has the stress, no fracture grid" || ko "main XDMF: stress missing or fracture grid in it"
  check "partly slipping fracture, 1 vs 2 ranks (1e-8)" $PY tests/verification/check_contact.py same \
    "$out/block_mumps1" "$out/block_mumps" 1e-8
fi
# (the reordered preconditioner with S* by one V-cycle: the reference of the
# stronger S* solves below)
for blk in reordered classical augmented; do
  deck "block_$blk" tests/decks/contact_block.nml -e "s#method = 'mumps'#method = 'fgmres', rtol = 1.0e-10#"
  printf "&contact\n  block = '%s'%s\n/\n" "$blk" "$([ "$blk" = reordered ] && echo ", schur_solve = 'vcycle'")" \
    >> "$out/block_$blk.nml"
  run "block_$blk" 2 && check "FGMRES with the $blk preconditioner vs MUMPS (1e-6)" $PY \
    tests/verification/check_contact.py same "$out/block_mumps" "$out/block_$blk" 1e-6
done
# S* solved by an inner CG, or by 2 CG steps with BoomerAMG (schur_solve =
# 'pcg', refreshed in place at every Newton iteration): the same answer in
# fewer outer iterations
stronger block_inner block_reordered block_mumps "reordered with S* by an inner CG" \
  "&contact\n  block = 'reordered', schur_solve = 'inner_cg'\n/\n"
stronger block_pcg block_reordered block_mumps "reordered with S* by 2 PCG steps" \
  "&contact\n  block = 'reordered', schur_solve = 'pcg'\n/\n"
# the exact Newton loop (every solve to rtol): by default the solves of the
# iterations whose statuses may still move stop at &contact moving_rtol (the
# first of a step after one that changed statuses, each after an update that
# did): the same answer, fewer FGMRES iterations in all; a step after one in
# which no status changed starts with a solve to rtol, as the exact loop
for m in moving exact; do
  deck "block_$m" tests/decks/contact_block.nml -e "s#method = 'mumps'#method = 'fgmres', rtol = 1.0e-10#" \
    -e "s#n_steps = 2#n_steps = 3#"
  printf "&contact\n  block = 'reordered', schur_solve = 'pcg'%s\n/\n" "$([ $m = exact ] && echo ', moving_rtol = 0.0')" \
    >> "$out/block_$m.nml"
done
if run block_moving 2 && run block_exact 2; then
  check "the default loop (moving_rtol = 1e-3) vs the exact loop, 3 load steps (1e-6)" $PY \
    tests/verification/check_contact.py same "$out/block_exact" "$out/block_moving" 1e-6
  fewer block_moving block_exact "the default loop (moving_rtol = 1e-3)"
  a=$(newtons block_moving); b=$(newtons block_exact)
  [ -n "$a" ] && [ "${a##* }" = "${b##* }" ] && ok "Newton iterations per step: default $a, exact loop $b (the same in the last step, after one with no status change)" || \
    ko "Newton iterations per step: default $a, exact loop $b (the last step's should be the same)"
fi
grep -q "stick/slip/open [0-9]*/[1-9]" "$out/block_mumps.log" && ok "the block case has slipping elements" || \
  ko "the block case has no slipping element"

# the face-bubble space: stick = intact; the partly slipping fracture on 1
# and 2 ranks, and with FGMRES and its default block preconditioner
# ('augmented', with no H_t) against MUMPS, at the same tolerances
deck stick_bubble tests/decks/contact_stick.nml
space stick_bubble bubble
run stick_bubble 2 && check "stick fault = intact solution (space bubble, MUMPS, 2 ranks)" $PY \
  tests/verification/check_contact.py stick "$out/stick_bubble"
deck block_mumps_bubble tests/decks/contact_block.nml
deck block_mumps1_bubble tests/decks/contact_block.nml
deck block_augmented_bubble tests/decks/contact_block.nml -e "s#method = 'mumps'#method = 'fgmres', rtol = 1.0e-10#"
for s in block_mumps_bubble block_mumps1_bubble block_augmented_bubble; do space "$s" bubble; done
if run block_mumps_bubble 2 && run block_mumps1_bubble 1; then
  check "space bubble: partly slipping fracture, 1 vs 2 ranks (1e-8)" $PY tests/verification/check_contact.py same \
    "$out/block_mumps1_bubble" "$out/block_mumps_bubble" 1e-8
  grep -q "stick/slip/open [0-9]*/[1-9]" "$out/block_mumps_bubble.log" && ok "space bubble: the block case slips" || \
    ko "space bubble: the block case has no slipping element"
  run block_augmented_bubble 2 && check "space bubble: FGMRES with the augmented preconditioner vs MUMPS (1e-6)" $PY \
    tests/verification/check_contact.py same "$out/block_mumps_bubble" "$out/block_augmented_bubble" 1e-6
  # W(3,3) cycles on S* (the configuration whose counts stay within 1.3x
  # over the 5 levels, doc/contact.md: stable space), and S* by 2 CG steps
  stronger block_augmented_bubble_w3 block_augmented_bubble block_mumps_bubble \
    "space bubble: augmented with W(3,3) cycles on S*" \
    "&contact\n  space = 'bubble'\n/\n&amg\n  cycle_type = 'w', num_sweeps = 3\n/\n"
  stronger block_augmented_bubble_pcg block_augmented_bubble block_mumps_bubble \
    "space bubble: augmented with S* by 2 PCG steps" "&contact\n  space = 'bubble', schur_solve = 'pcg'\n/\n"
fi

# S*'s default solve follows the block: two CG steps for 'reordered', one
# V-cycle for 'classical' and the bubble space's 'augmented'
for r in block_mumps1:pcg block_classical:vcycle block_mumps1_bubble:vcycle; do
  grep -q "^  schur_solve *= '${r#*:}'" "$out/${r%:*}_parameters.nml" && \
    ok "${r%:*}: schur_solve resolved to '${r#*:}'" || ko "${r%:*}: schur_solve not resolved to '${r#*:}'"
done
# contact keeps l1 Gauss-Seidel (elasticity and biot default to Chebyshev)
grep -q "^  relax_type *= 'l1-gs'" "$out/block_mumps1_parameters.nml" && ok "contact: &amg relax_type 'l1-gs' by default" \
  || ko "contact: &amg relax_type is not 'l1-gs' by default ($out/block_mumps1_parameters.nml)"

# a displacement with a load history in load steps: the top's uz at load
# factor t is -1e-4 m x t x f(t), f from the table (f(0.5) = 1, f(1) = 3);
# the prescribed values once lagged a step behind (f of the step before)
printf '0.0 0.0\n0.5 1.0\n1.0 3.0\n' > "$out/ramp.tab"
deck stick_history tests/decks/contact_stick.nml \
  -e "/set = 'zmax'/,/^\//s#type = 'traction'#type = 'displacement'#" \
  -e "s#traction = 0.0, 0.0, -1.0e7#uz = -1.0e-4, history = 'ramp.tab'#"
printf "&time\n  n_steps = 2\n/\n" >> "$out/stick_history.nml"
if run stick_history 2; then
  if r=$($PY - "$out/stick_history" <<'PYEOF'
import sys, h5py, numpy as np
base = sys.argv[1]
z = h5py.File(base + '_mesh.h5', 'r')['coords'][:, 2]
top = np.abs(z - z.max()) < 1e-12
worst = 0.0
for step, want in ((1, -5.0e-5), (2, -3.0e-4)):   # load step n: output file n - 1
    uz = h5py.File('%s_%04d.h5' % (base, step - 1), 'r')['displacement'][:, 2][top]
    worst = max(worst, np.max(np.abs(uz - want)) / abs(want))
print('%.1e' % worst)
sys.exit(0 if worst < 1e-12 else 1)
PYEOF
  ); then ok "load history of a prescribed displacement in load steps: top uz = -1e-4 t f(t) at both steps (rel. $r)"
  else ko "load history of a prescribed displacement in load steps: top uz off by $r (relative)"; fi
fi

echo "suite contact: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
