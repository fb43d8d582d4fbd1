#!/usr/bin/env bash
# Bad input must stop geoblock on every rank with exit status 2 and one line
# "geoblock: error: ..." that names what is wrong: no backtrace, no compiler
# note or STOP line, no hang (timeout). Each tests/decks/bad_*.nml starts with
# "! expect: TEXT", the text the message must contain; command-line cases
# follow the decks.
set -u
cd "$(dirname "$0")/.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
# a rank that exits with status 2 after MPI_Finalize (a refused deck) makes
# mpirun stop the job; its default grace of 1 s before SIGKILL cost each such
# case 2 s of wall time
export OMPI_MCA_odls_base_sigkill_timeout=0
exe=${GEOBLOCK:-bin/geoblock}   # GEOBLOCK=bin/geoblock-debug runs the suite on the checked build
pass=0; fail=0
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
n_case=0
# files a case wrote in the source tree outside build/test-out (its output
# directory there) and .git: there must be none
stray() {
  find . \( -path ./build/test-out -o -path ./out -o -path ./.git \) -prune -o -type f -newer "$stamp" -print | head -3
}
# one_case name, ranks, deck (or arguments), expected text: prints "  ok ..."
# or "  FAIL ..." (files $errf and $stamp of its own)
one_case() {
  local name=$1 np=$2 deck=$3 expect=$4 out rc nerr strays
  touch "$stamp"
  # shellcheck disable=SC2086
  out=$(OMPI_MCA_orte_tmpdir_base=$ompi_dir timeout 120 mpirun --oversubscribe -np "$np" "$exe" $deck \
        2> "$errf" < /dev/null)
  rc=$?
  out="$out"$'\n'"$(cat "$errf")"
  if [ "$rc" -eq 124 ]; then
    echo "  FAIL  $name: hung (timeout)"; return 1
  fi
  if [ "$rc" -ne 2 ]; then
    echo "  FAIL  $name: exit status $rc, not 2"; echo "$out" | head -5 | sed 's/^/        /'
    return 1
  fi
  nerr=$(grep -c '^geoblock: error: ' "$errf")
  if [ "$nerr" -ne 1 ]; then
    echo "  FAIL  $name: $nerr 'geoblock: error:' lines on stderr, not one"; echo "$out" | head -5 | sed 's/^/        /'
    return 1
  fi
  if ! grep -qF -- "$expect" <<< "$out"; then
    echo "  FAIL  $name: message lacks \"$expect\""; echo "$out" | head -5 | sed 's/^/        /'
    return 1
  fi
  if grep -qiE 'backtrace|#0 |SIGSEGV|Floating-point exception|^STOP|^ERROR STOP|^Note: ' <<< "$out"; then
    echo "  FAIL  $name: a backtrace or signal in the output"; return 1
  fi
  strays=$(stray)
  if [ -n "$strays" ]; then
    echo "  FAIL  $name: wrote outside its output directory: $(echo "$strays" | tr '\n' ' ')"; return 1
  fi
  echo "  ok    $name ($np ranks): $(grep -m1 -F -- "$expect" <<< "$out" | cut -c1-150)"
}
# check: the same, in the background, two cases at a time (most of a case
# is mpirun's start-up); collect waits for them and counts, in order. Each
# case has its own Open MPI session directory: in the shared default one,
# /tmp/ompi.<host>.<uid>, a job that ends removes the tree another job is
# creating its directory in ("A call to mkdir was unable to create the
# desired directory", exit 1; Open MPI 4.x, open-mpi/ompi#8510)
check() {
  n_case=$((n_case + 1))
  mkdir -p "$work/$n_case.ompi"
  ( errf=$work/$n_case.err stamp=$work/$n_case.stamp ompi_dir=$work/$n_case.ompi one_case "$@" \
      > "$work/$n_case.out" 2>&1 ) &
  while [ "$(jobs -rp | wc -l)" -ge 2 ]; do wait -n; done
}
collected=0
collect() {
  local i
  wait
  for ((i = collected + 1; i <= n_case; i++)); do
    cat "$work/$i.out"
    if grep -q '^  ok' "$work/$i.out"; then pass=$((pass + 1)); else fail=$((fail + 1)); fi
  done
  collected=$n_case
}
for deck in tests/decks/bad_*.nml; do
  expect=$(head -n 1 "$deck" | sed -E 's/^! expect: //')
  for np in 1 2; do
    check "$(basename "$deck" .nml)" "$np" "$deck" "$expect"
  done
done
check missing_deck_file 2 tests/decks/no_such_deck.nml "cannot read deck 'tests/decks/no_such_deck.nml'"
check no_argument 1 "" "no deck given; usage: geoblock"
check unknown_option 1 "--frobnicate tests/decks/good_base.nml" "unknown option '--frobnicate'"
check two_decks 2 "tests/decks/good_base.nml tests/decks/good_base.nml" "more than one deck given"
check long_argument 1 "$(printf 'd%.0s' $(seq 600))" "argument 1 is longer than 512 characters"
check deck_is_directory 2 tests/decks "cannot read deck 'tests/decks': it is a directory"
check check_bad_deck 2 "--check tests/decks/bad_nan_value.nml" "variable young: 'nan' is not a finite number"
collect
# a full disk: a 200 kB tmpfs, where this machine lets us mount one
full=$(mktemp -d)
if mount -t tmpfs -o size=200k tmpfs "$full" 2> /dev/null; then
  mkdir -p build/test-out/deck_errors
  sed -e "s#nx = 2, ny = 2, nz = 2#nx = 20, ny = 20, nz = 20#" -e "s#dir = 'build/test-out'#dir = '$full/out'#" \
      -e "s#fields = .false.#fields = .true.#" tests/decks/good_base.nml > build/test-out/deck_errors/disk_full.nml
  for np in 1 2; do
    rm -rf "$full/out"
    check disk_full "$np" build/test-out/deck_errors/disk_full.nml "(is the disk full, or the file system read-only?)"
    collect
  done
  umount "$full"
else
  echo "  skip  disk_full: no tmpfs can be mounted here"
fi
rmdir "$full"
# --check reads a good deck, echoes it and runs nothing
if out=$(timeout 120 mpirun --oversubscribe -np 2 "$exe" --check tests/decks/good_base.nml 2>&1 < /dev/null) && \
   grep -q "is valid (physics elasticity); nothing was run" <<< "$out"; then
  echo "  ok    --check of good_base: valid, nothing run"; pass=$((pass + 1))
else
  echo "  FAIL  --check of good_base"; fail=$((fail + 1))
fi
for opt in --help --version; do
  if out=$(timeout 60 mpirun -np 1 "$exe" $opt 2>&1 < /dev/null) && grep -q "geoblock" <<< "$out"; then
    echo "  ok    $opt: $(head -1 <<< "$out")"; pass=$((pass + 1))
  else
    echo "  FAIL  $opt"; fail=$((fail + 1))
  fi
done
# the good base deck must run (guards against a reader that rejects everything)
if timeout 120 mpirun --oversubscribe -np 2 "$exe" tests/decks/good_base.nml > /dev/null 2>&1; then
  echo "  ok    good_base runs"; pass=$((pass + 1))
else
  echo "  FAIL  good_base does not run"; fail=$((fail + 1))
fi
# a quoted string continued on the next line is joined without padding
mkdir -p build/test-out/deck_errors
{ sed '/&output/,$d' tests/decks/good_base.nml
  printf "&output\n  dir = 'build/test-out/deck_errors', prefix = 'joined_\npart', fields = .false.\n/\n"; } \
  > build/test-out/deck_errors/continued.nml
rm -f build/test-out/deck_errors/joined_part.log
if timeout 120 mpirun -np 1 "$exe" build/test-out/deck_errors/continued.nml > /dev/null 2>&1 && \
   [ -f build/test-out/deck_errors/joined_part.log ]; then
  echo "  ok    a string continued over two lines is joined (prefix joined_part)"; pass=$((pass + 1))
else
  echo "  FAIL  a string continued over two lines: no build/test-out/deck_errors/joined_part.log"; fail=$((fail + 1))
fi
echo "suite deck_errors: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
