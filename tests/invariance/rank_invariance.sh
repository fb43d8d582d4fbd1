#!/usr/bin/env bash
# Results do not depend on the number of ranks beyond round-off, and a run
# repeated on the same number of ranks gives the same bits.
#  - ranks: the same deck on 1, 2 and 4 ranks (4 oversubscribed), fields
#    matched by node coordinates and cell centres: elasticity (
#    FGMRES + BoomerAMG, rtol 1e-13) to 1e-10, Biot (block preconditioner)
#    and contact (reordered block preconditioner) with rtol 1e-12 to 1e-8;
#  - repeats: every solver (FGMRES with each physics' preconditioner, CG,
#    MUMPS) run twice on 2 ranks, every HDF5 file identical to the bit
#    (tools/compare_outputs.py --tol 0).
set -u
cd "$(dirname "$0")/../.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
PY=${PYTHON:-/usr/bin/python3}
pass=0; fail=0
base=build/test-out/invariance
rm -rf "$base"
mkdir -p "$base"

# run NAME NP DECK [SOLVER-LINE]: the deck with its &output dir set to
# $base/NAME (and its &solver group replaced by SOLVER-LINE when given)
run() {
  local name=$1 np=$2 deck=$3 solver=${4:-}
  local nml="$base/$name.nml"
  sed -E "s#^( *dir *= *)'[^']*'#\1'$base/$name'#" "$deck" > "$nml"
  if [ -n "$solver" ]; then
    "$PY" - "$nml" "$solver" <<'EOF'
import re, sys
path, solver = sys.argv[1], sys.argv[2]
text = open(path).read()
text = re.sub(r"&solver\b.*?\n/\n", "&solver\n  " + solver + "\n/\n", text, flags=re.S)
open(path, "w").write(text)
EOF
  fi
  if timeout 300 mpirun --oversubscribe -np "$np" bin/geoblock "$nml" > "$base/$name.log" 2>&1; then
    echo "  ok    $name ran on $np rank(s)"; pass=$((pass + 1))
  else
    echo "  FAIL  $name on $np rank(s), see $base/$name.log"; fail=$((fail + 1))
  fi
}

# ranks CASE DECK TOL FIELD...: CASE on 1, 2 and 4 ranks, 1 vs 2 and 1 vs 4
ranks() {
  local case=$1 deck=$2 tol=$3; shift 3
  local np out
  for np in 1 2 4; do run "${case}_np$np" $np "$deck"; done
  for np in 2 4; do
    if out=$($PY tests/invariance/compare_runs.py "$base/${case}_np1" "$base/${case}_np$np" inv "$tol" "$@" 2>&1); then
      echo "  ok    $case, 1 vs $np ranks: $(echo "$out" | tr '\n' ';')"; pass=$((pass + 1))
    else
      echo "  FAIL  $case, 1 vs $np ranks: $(echo "$out" | tr '\n' ';')"; fail=$((fail + 1))
    fi
  done
}

# repeat CASE DECK SOLVER-LINE: two runs on 2 ranks, identical bits
repeat() {
  local case=$1 deck=$2 solver=$3 out
  run "${case}_a" 2 "$deck" "$solver"
  run "${case}_b" 2 "$deck" "$solver"
  if out=$($PY tools/compare_outputs.py "$base/${case}_a" "$base/${case}_b" --tol 0 2>&1 | tail -1) && \
     grep -q " 0 differ" <<< "$out"; then
    echo "  ok    $case repeated on 2 ranks: $out"; pass=$((pass + 1))
  else
    echo "  FAIL  $case repeated on 2 ranks: $out"; fail=$((fail + 1))
  fi
}

ranks elasticity tests/decks/invariance.nml 1e-10 displacement stress
ranks biot tests/decks/invariance_biot.nml 1e-8 displacement pressure stress
ranks contact tests/decks/invariance_contact.nml 1e-8 displacement stress

repeat elasticity_fgmres tests/decks/invariance.nml "method = 'fgmres', precon = 'boomeramg', rtol = 1.0e-10"
repeat elasticity_cg tests/decks/invariance.nml "method = 'cg', precon = 'afsai', rtol = 1.0e-10"
repeat elasticity_mumps tests/decks/invariance.nml "method = 'mumps'"
repeat biot_block tests/decks/invariance_biot.nml "method = 'fgmres', rtol = 1.0e-10"
repeat biot_explicit tests/decks/invariance_biot.nml "method = 'fgmres', decoupling = 'explicit', rtol = 1.0e-10"
repeat biot_mumps tests/decks/invariance_biot.nml "method = 'mumps'"
repeat contact_block tests/decks/invariance_contact.nml "method = 'fgmres', rtol = 1.0e-10"
repeat contact_mumps tests/decks/invariance_contact.nml "method = 'mumps'"
echo "suite rank_invariance: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
