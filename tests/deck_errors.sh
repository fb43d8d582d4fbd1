#!/usr/bin/env bash
# Bad input must stop geoblock on every rank with a message that names what is
# wrong, a nonzero exit, no backtrace and no hang. Each tests/decks/bad_*.nml
# starts with "! expect: TEXT", the text the message must contain.
set -u
cd "$(dirname "$0")/.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
exe=bin/geoblock
pass=0; fail=0
check() {  # name, ranks, deck, expected text
  local name=$1 np=$2 deck=$3 expect=$4 out rc
  out=$(timeout 120 mpirun --oversubscribe -np "$np" "$exe" "$deck" 2>&1 < /dev/null)
  rc=$?
  if [ "$rc" -eq 124 ]; then
    echo "  FAIL  $name: hung (timeout)"; fail=$((fail + 1)); return
  fi
  if [ "$rc" -eq 0 ]; then
    echo "  FAIL  $name: exit status 0"; fail=$((fail + 1)); return
  fi
  if ! grep -qF -- "$expect" <<< "$out"; then
    echo "  FAIL  $name: message lacks \"$expect\""; echo "$out" | head -5 | sed 's/^/        /'
    fail=$((fail + 1)); return
  fi
  if grep -qiE 'backtrace|#0 |SIGSEGV|Floating-point exception' <<< "$out"; then
    echo "  FAIL  $name: a backtrace or signal in the output"; fail=$((fail + 1)); return
  fi
  echo "  ok    $name ($np ranks): $(grep -m1 -F -- "$expect" <<< "$out" | cut -c1-150)"
  pass=$((pass + 1))
}
for deck in tests/decks/bad_*.nml; do
  expect=$(head -n 1 "$deck" | sed -E 's/^! expect: //')
  for np in 1 2; do
    check "$(basename "$deck" .nml)" "$np" "$deck" "$expect"
  done
done
check missing_deck_file 2 tests/decks/no_such_deck.nml "cannot read deck 'tests/decks/no_such_deck.nml'"
check no_argument 1 "" "usage: geoblock DECK.nml"
# the good base deck must run (guards against a reader that rejects everything)
if timeout 120 mpirun --oversubscribe -np 2 "$exe" tests/decks/good_base.nml > /dev/null 2>&1; then
  echo "  ok    good_base runs"; pass=$((pass + 1))
else
  echo "  FAIL  good_base does not run"; fail=$((fail + 1))
fi
echo "suite deck_errors: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
