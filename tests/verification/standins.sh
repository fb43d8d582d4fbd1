#!/usr/bin/env bash
# The seed's Biot cases reduced (tests/decks/treporti_small.nml, 2,268
# cells; reservoir_small.nml, 6,000 cells: the layers, load and wells of
# input/treporti.nml and input/reservoir.nml on coarse meshes), each on 1
# and 2 ranks with FGMRES + the default block preconditioner (rtol 1e-10)
# and (Treporti) with MUMPS; MUMPS is left out on the Reservoir: on its
# system (shales of 1e-18 m^2 beside a 1e-13 sandstone) it leaves scaled
# residuals of 1e-7 to 3e-6, above the direct solve's check, and its
# factorization alone took 20 s of the suite's budget:
#  - every solve converges (no 'did not converge', every step line);
#  - FGMRES against MUMPS, last step, pressure and displacement in the max
#    norm relative to the field's largest value: within 1e-6, that is 1e4 x
#    rtol, the factor a relative residual of the scaled system may grow by
#    through the blocks' condition (measured below 4e-10);
#  - MUMPS on 1 against 2 ranks: round-off, 1e-10 (the same bound as
#    mandel.sh); FGMRES on 1 against 2 ranks: 1e-6 (each within the above;
#    for the Reservoir this is the only rank comparison, not round-off);
#  - physics (check_standins.py): Treporti's settlement under the load
#    positive, growing and above ten times the far corner's, and at 10 days
#    the sand between two clay layers drained below both; the Reservoir's
#    pressures down at the producers and up at the injectors, and the closed
#    block's fluid balance (ground heave + storage = the wells' volume) to
#    1e-8 of the wells' volume with FGMRES (100 x rtol: the balance is the
#    sum of the mass rows' residuals).
set -u
cd "$(dirname "$0")/../.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
PY=${PYTHON:-/usr/bin/python3}
out=build/test-out/standins
rm -rf "$out"; mkdir -p "$out"
pass=0; fail=0
ok() { echo "  ok    $1"; pass=$((pass + 1)); }
ko() { echo "  FAIL  $1"; fail=$((fail + 1)); }
run() {   # run CASE SOLVER RANKS: deck and run, status in $out/NAME.rc
  local name=$1_$2_np$3 solver="method = 'mumps'"
  [ "$2" = fgmres ] && solver="method = 'fgmres', precon = 'block', rtol = 1.0e-10"
  sed -e "s#method = 'fgmres', precon = 'block', rtol = 1.0e-8#$solver#" \
      -e "s#dir = 'build/test-out/standins'#dir = '$out/$name'#" "tests/decks/$1_small.nml" > "$out/$name.nml"
  timeout 300 mpirun --oversubscribe -np "$3" bin/geoblock "$out/$name.nml" > "$out/$name.stdout" 2>&1 < /dev/null
  echo $? > "$out/$name.rc"
}
# the 1-rank runs two at a time (2 cores), then the 2-rank runs
run treporti fgmres 1 & run treporti mumps 1 & wait
run reservoir fgmres 1
run treporti fgmres 2; run treporti mumps 2; run reservoir fgmres 2
solvers() { case $1 in treporti) echo "fgmres mumps" ;; reservoir) echo fgmres ;; esac; }
for c in treporti reservoir; do
  for name in $(for s in $(solvers "$c"); do echo "${c}_${s}_np1 ${c}_${s}_np2"; done); do
    n=$(grep -c '^step ' "$out/$name.stdout")
    if [ "$(cat "$out/$name.rc")" = 0 ] && [ "$n" = 2 ] && ! grep -q 'did not converge' "$out/$name.stdout"; then
      ok "$name: converged, $n steps ($(grep '^step ' "$out/$name.stdout" | sed -E 's/.*iterations +([0-9]+).*/\1/' | tr '\n' ' ')iterations)"
    else
      ko "$name: exit $(cat "$out/$name.rc"), $n step lines, see $out/$name.stdout"
    fi
  done
  cmp() {   # cmp A B TOL WHAT
    if r=$($PY tests/invariance/compare_runs.py "$out/$1" "$out/$2" "$c" "$3" pressure displacement 2>&1); then
      ok "$c, $4: $(echo "$r" | tail -2 | tr '\n' ' ')"
    else
      ko "$c, $4: $(echo "$r" | tr '\n' ' ')"
    fi
  }
  if [ "$c" = treporti ]; then
    cmp ${c}_mumps_np1 ${c}_fgmres_np1 1e-6 "FGMRES vs MUMPS, 1 rank"
    cmp ${c}_mumps_np2 ${c}_fgmres_np2 1e-6 "FGMRES vs MUMPS, 2 ranks"
    cmp ${c}_mumps_np1 ${c}_mumps_np2 1e-10 "MUMPS 1 vs 2 ranks"
  fi
  cmp ${c}_fgmres_np1 ${c}_fgmres_np2 1e-6 "FGMRES 1 vs 2 ranks"
  for s in $(solvers "$c"); do
    tol=1e-9; [ "$s" = fgmres ] && tol=1e-8
    r=$($PY tests/verification/check_standins.py "$c" "$out/${c}_${s}_np2" --balance-tol "$tol" 2>&1); rc=$?
    while read -r line; do
      case "$line" in FAIL*) ko "$c, $s (2 ranks): ${line#FAIL }" ;; *) ok "$c, $s (2 ranks): $line" ;; esac
    done < <(grep -E '^(FAIL )?t = |^(FAIL )?(settlement|far|at 10 days)' <<< "$r")
    [ "$rc" -ne 0 ] && ! grep -q '^FAIL' <<< "$r" && ko "$c, $s (2 ranks): check_standins.py failed: $(tail -1 <<< "$r")"
  done
done
echo "suite standins: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
