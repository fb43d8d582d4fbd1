#!/usr/bin/env bash
# postproc/compare_runs.py on the fracture in a block (tests/decks/contact_fgmres.nml):
#  - the deck on 1 and 2 ranks: every field within 1e-8 of each other
#    (other partitions and global numbering, matched by position);
#  - with a larger friction angle the slip and the statuses differ: --tol
#    fails naming them, without --tol the table alone (exit 0);
#  - refused with one line: a directory without a run, a step it did not
#    write, another mesh, steps at other times, a negative --tol.
set -u
cd "$(dirname "$0")/../.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
PY=${PYTHON:-/usr/bin/python3}
base=build/test-out/compare_runs
rm -rf "$base"; mkdir -p "$base"
pass=0; fail=0
ok() { echo "  ok    $1"; pass=$((pass + 1)); }
ko() { echo "  FAIL  $1"; fail=$((fail + 1)); }
cmp() { $PY postproc/compare_runs.py "$@" 2>&1; }

# deck name, ranks, sed edits
run() {
  sed -E "s#^( *dir *= *)'[^']*'#\1'$base/$1'#; $3" tests/decks/contact_fgmres.nml > "$base/$1.nml"
  if timeout 300 mpirun --oversubscribe -np "$2" bin/geoblock "$base/$1.nml" > "$base/$1.out" 2>&1; then
    ok "run $1 on $2 rank(s)"
  else
    ko "run $1 on $2 rank(s), see $base/$1.out"
  fi
}
run np1 1 ''
run np2 2 ''
run friction 1 's/friction_angle = 10.0/friction_angle = 25.0/'
run coarse 1 's/nx = 12, ny = 12, nz = 12/nx = 8, ny = 8, nz = 8/'
run steps 1 's/n_steps = 2/n_steps = 4/'
A=$base/np1/contact_block

if r=$(cmp "$A" "$base/np2/contact_block" --tol 1e-8) && grep -q '^every field within 1e-08$' <<< "$r" && \
   grep -q '^fractures/status .* 0 of ' <<< "$r" && grep -q '^displacement ' <<< "$r"; then
  ok "1 against 2 ranks: every field within 1e-8 ($(grep '^displacement ' <<< "$r" | tr -s ' '))"
else
  ko "1 against 2 ranks: $r"
fi
if r=$(cmp "$A" "$base/friction/contact_block" --tol 1e-8); then
  ko "another friction angle within 1e-8: $r"
elif grep -q '^beyond 1e-08: .*fractures/slip' <<< "$r" && grep -q '^beyond 1e-08: .*displacement' <<< "$r"; then
  ok "another friction angle: exit 1, $(grep '^beyond' <<< "$r" | cut -c1-80)..."
else
  ko "another friction angle, not named: $r"
fi
if r=$(cmp "$A" "$base/friction/contact_block") && grep -q '^fractures/slip_magnitude ' <<< "$r" && \
   ! grep -q '^beyond' <<< "$r"; then
  ok "without --tol: the table, exit 0"
else
  ko "without --tol: $r"
fi
refused() {   # label, expected text, arguments
  local label=$1 want=$2; shift 2
  if r=$(cmp "$@"); then
    ko "$label: exit 0"
  elif [ "$(wc -l <<< "$r")" -eq 1 ] && grep -q "^compare_runs.py: error: .*$want" <<< "$r"; then
    ok "$label: $r"
  else
    ko "$label: $r"
  fi
}
refused "no run there" "no geoblock mesh file" "$A" "$base/none/contact_block"
refused "a step not written" "no output step 9" "$A" "$base/np2/contact_block" --step 9
refused "another mesh" "other meshes" "$A" "$base/coarse/contact_block"
refused "steps at other times" "other times" "$A" "$base/steps/contact_block" --step 1
refused "a negative --tol" "--tol must be >= 0" "$A" "$base/np2/contact_block" --tol -1

echo "suite compare_runs: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
