#!/usr/bin/env bash
# The High Island 24L stand-in at its small size (tests/decks/hi24l_small.nml,
# meshes/hi24l_small.msh): 32 faults that cross, meet in T junctions and end
# at tips, a geostatic start and one load step, on 1 and 2 ranks.
#  - the mesh read as make_hi24l.py counted it (11,631 nodes after the
#    split, 2,138 interface elements, n_u = 34,893, n_t = 6,414);
#  - step 0 keeps every element stuck, the load step (a 20 MPa depletion of
#    the reservoir sands in the fault block between f02 and f06) makes some
#    slip or open
#  - the depleted cells are those of the blocks that check_compartment.py
#    finds on its own in the written mesh (a fault that cuts a sand from
#    side to side bounds the block, faults that end inside do not), on 1
#    and 2 ranks
#    (the active set works across the junctions);
#  - 1 vs 2 ranks: the same statuses and the same stress to 1e-7 (the
#    stabilization edges at crossing and T-junction lines once depended on
#    the partition's node numbering: fault_edges).
set -u
cd "$(dirname "$0")/../.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
PY=${PYTHON:-/usr/bin/python3}
base=build/test-out/hi24l
rm -rf "$base"; mkdir -p "$base"
pass=0; fail=0
ok() { echo "  ok    $1"; pass=$((pass + 1)); }
ko() { echo "  FAIL  $1"; fail=$((fail + 1)); }

for np in 1 2; do
  sed -E "s#^( *dir *= *)'[^']*'#\1'$base/np$np'#; s#'\.\./\.\./meshes/#'$PWD/meshes/#" \
    tests/decks/hi24l_small.nml > "$base/np$np.nml"
  if timeout 600 mpirun --oversubscribe -np $np bin/geoblock "$base/np$np.nml" > "$base/np$np.out" 2>&1; then
    ok "the small deck ran on $np rank(s)"
  else
    ko "the small deck on $np rank(s), see $base/np$np.out"
  fi
done
log=$base/np1.out
if grep -q 'faults: 2138 interface elements, .* (2187 nodes added)' "$log" && \
   grep -q 'unknowns: u 34893, t 6414 ' "$log"; then
  ok "mesh as counted by make_hi24l.py: 2138 interface elements, n_u 34893, n_t 6414"
else
  ko "mesh counts: $(grep -E '^(faults|unknowns):' "$log" | tr '\n' ';')"
fi
s0=$(grep -m1 '^load step 0/1' "$log" | sed -E 's/.*stick\/slip\/open ([0-9]+\/[0-9]+\/[0-9]+).*/\1/')
s1=$(grep -m1 '^load step 1/1' "$log" | sed -E 's/.*stick\/slip\/open ([0-9]+\/[0-9]+\/[0-9]+).*/\1/')
if [ "$s0" = "2138/0/0" ]; then ok "step 0: every element sticks ($s0)"; else ko "step 0: stick/slip/open $s0"; fi
case "$s1" in
  2138/0/0|'') ko "load step: nothing slips or opens ($s1)" ;;
  *) ok "load step: stick/slip/open $s1" ;;
esac
s1b=$(grep -m1 '^load step 1/1' "$base/np2.out" | sed -E 's/.*stick\/slip\/open ([0-9]+\/[0-9]+\/[0-9]+).*/\1/')
if [ "$s1" = "$s1b" ]; then ok "1 vs 2 ranks: the same statuses ($s1)"; else ko "1 vs 2 ranks: statuses $s1 vs $s1b"; fi
for np in 1 2; do
  if r=$($PY tests/driver/check_compartment.py "$base/np$np/hi24l_small" 1 -2.0e7 \
         6000,4000,-1580 6000,4000,-1690 6000,4000,-1810 2>&1); then
    ok "depleted compartment, $np rank(s): $r"
  else
    ko "depleted compartment, $np rank(s): $r"
  fi
done
# the reservoir-interval picture of make bench (plot_faults.py --z-range)
if r=$($PY postproc/plot_faults.py "$base/np1/hi24l_small" --z-range=-1500,-1900 --z-scale 6 \
       -o "$base/reservoir.png" 2>&1) && [ -s "$base/reservoir.png" ] && grep -q '^figure: ' <<< "$r"; then
  ok "plot_faults.py --z-range: $base/reservoir.png"
else
  ko "plot_faults.py --z-range: $(tail -1 <<< "$r")"
fi
if r=$($PY postproc/plot_faults.py "$base/np1/hi24l_small" --z-range=-5000,-4500 -o "$base/none.png" 2>&1); then
  ko "plot_faults.py with a depth window holding no element: exit 0"
else
  ok "plot_faults.py with a depth window holding no element: $(tail -1 <<< "$r")"
fi
if out=$($PY tests/invariance/compare_runs.py "$base/np1" "$base/np2" hi24l_small 1e-7 stress 2>&1); then
  ok "1 vs 2 ranks: $(echo "$out" | tr '\n' ';')"
else
  ko "1 vs 2 ranks: $(echo "$out" | tr '\n' ';')"
fi
echo "suite hi24l: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
