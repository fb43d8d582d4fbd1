#!/usr/bin/env bash
# The same deck on 1, 2 and 4 ranks (4 oversubscribed): displacement and
# stress agree to 1e-10 relative (fields matched by coordinates).
set -u
cd "$(dirname "$0")/../.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
PY=${PYTHON:-/usr/bin/python3}
pass=0; fail=0
base=build/test-out/invariance
rm -rf "$base"
mkdir -p "$base"
for np in 1 2 4; do
  sed "s#build/test-out/inv#$base/np$np#" tests/decks/invariance.nml > "$base/np$np.nml"
  if timeout 300 mpirun --oversubscribe -np $np bin/geoblock "$base/np$np.nml" > "$base/np$np.log" 2>&1; then
    echo "  ok    run on $np rank(s)"; pass=$((pass + 1))
  else
    echo "  FAIL  run on $np rank(s), see $base/np$np.log"; fail=$((fail + 1))
  fi
done
for np in 2 4; do
  if out=$($PY tests/invariance/compare_runs.py "$base/np1" "$base/np$np" inv 1e-10 displacement stress 2>&1); then
    echo "  ok    1 vs $np ranks: $(echo "$out" | tr '\n' ';')"; pass=$((pass + 1))
  else
    echo "  FAIL  1 vs $np ranks: $(echo "$out" | tr '\n' ';')"; fail=$((fail + 1))
  fi
done
echo "suite rank_invariance: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
