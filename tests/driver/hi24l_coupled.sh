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
#    more compressive (postproc/field_coupled.py sign);
#  - FGMRES with the fractures' subspace correction runs it without a cut
#    and agrees with MUMPS to 1e-6.
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
# FGMRES with the fractures' subspace correction on (the deck has it off and
# MUMPS): the correction's coarse operator carries the leak-off to the
# matrix; without it FGMRES stalled here at a relative residual of 0.3-0.6
# and the step was cut 8 times. It must run without a cut and agree with
# the MUMPS run above to 1e-6 in every dataset of step 1 (relative
# max-norm, tools/compare_outputs.py).
sed -E -e "/subspace_correction = \.false\./d" -e "s#method = 'mumps'#method = 'fgmres', rtol = 1.0e-8, max_iter = 300#" \
  "$base/np2.nml" | sed -E "s#^( *dir *= *)'[^']*'#\1'$base/fg'#" > "$base/fg.nml"
if timeout 900 mpirun --oversubscribe -np 2 bin/geoblock "$base/fg.nml" > "$base/fg.out" 2>&1; then
  ok "FGMRES with the subspace correction ran on 2 ranks"
else
  ko "FGMRES with the subspace correction on 2 ranks, see $base/fg.out"
fi
if grep -q 'cut in half' "$base/fg.out"; then ko "FGMRES with the subspace correction: a step was cut"; else ok "FGMRES with the subspace correction: no step cut"; fi
if r=$($PY - "$base/np2/small_0001.h5" "$base/fg/small_0001.h5" <<'PY' 2>&1
import sys
sys.path.insert(0, 'tools')
from compare_outputs import compare_h5
bad = compare_h5(sys.argv[1], sys.argv[2], 1e-6)
print('; '.join(f'{n}: {m}' for n, m in bad) or 'every dataset of step 1')
sys.exit(1 if bad else 0)
PY
); then
  ok "FGMRES against MUMPS within 1e-6: $(echo "$r" | tr '\n' ';')"
else
  ko "FGMRES against MUMPS: $(echo "$r" | tr '\n' ';')"
fi
echo "suite hi24l_coupled: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
