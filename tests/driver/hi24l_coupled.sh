#!/usr/bin/env bash
# The field case's smoke test (tests/decks/hi24l_coupled_small.nml: the
# HI24L stand-in's small mesh, physics 'poromechanics_faults' with a
# geostatic start, production from the compartment between f02 and f06 by
# a &source with a point in each sand), on 2 ranks:
#  - it runs: step 0 (the in-situ state, faults bonded) and one production
#    step, every element sticks in step 0;
#  - the sign of the coupling: in the produced block of sand_2 the matrix
#    pressure falls, and on the fault elements beside the block the
#    fracture pressure falls and the effective normal traction becomes
#    more compressive (postproc/field_coupled.py sign).
set -u
cd "$(dirname "$0")/../.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
PY=${PYTHON:-/usr/bin/python3}
base=build/test-out/hi24l_coupled
rm -rf "$base"; mkdir -p "$base"
pass=0; fail=0
ok() { echo "  ok    $1"; pass=$((pass + 1)); }
ko() { echo "  FAIL  $1"; fail=$((fail + 1)); }

sed -E "s#^( *dir *= *)'[^']*'#\1'$base/np2'#; s#'\.\./\.\./meshes/#'$PWD/meshes/#" \
  tests/decks/hi24l_coupled_small.nml > "$base/np2.nml"
if timeout 900 mpirun --oversubscribe -np 2 bin/geoblock "$base/np2.nml" > "$base/np2.out" 2>&1; then
  ok "the coupled small deck ran on 2 ranks"
else
  ko "the coupled small deck on 2 ranks, see $base/np2.out"
fi
log=$base/np2/small.log
s0=$(grep -m1 '^time step 0 ' "$log" | sed -E 's/.*stick\/slip\/open ([0-9]+\/[0-9]+\/[0-9]+).*/\1/')
if [ "$s0" = "2138/0/0" ]; then ok "step 0: every element sticks ($s0)"; else ko "step 0: stick/slip/open '$s0'"; fi
if grep -q '^time step 1 ' "$log"; then ok "production step done"; else ko "no production step"; fi
if r=$($PY postproc/field_coupled.py sign "$base/np2/small" 1 6000,4000,-1690 2>&1); then
  ok "depletion: $(echo "$r" | tr '\n' ';')"
else
  ko "depletion signs: $(echo "$r" | tr '\n' ';')"
fi
echo "suite hi24l_coupled: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
