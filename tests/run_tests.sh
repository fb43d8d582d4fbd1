#!/usr/bin/env bash
# Run every suite listed in tests/suites.txt and end with "N passed, N failed".
# A line is "<ranks> <program> [args]" for a test program in bin/tests, or
# "script <path>" for a shell (.sh) or Python (.py) suite. Each suite prints "suite NAME: N passed, N failed";
# a suite that crashes or hangs (timeout) counts as one failure.
# Then the verification report, build/reports/verification.md
# (tools/verification_report.py), from the suites' logs, build/reports/suites.tsv
# (one row per suite: section, name, passed, failed, seconds, command) and
# the figures the verification suites record (build/reports/verification.tsv).
set -u
cd "$(dirname "$0")/.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
# a rank that exits with status 2 after MPI_Finalize (a refused deck) makes
# mpirun stop the job; its default grace of 1 s before SIGKILL cost each such
# case 2 s of wall time
export OMPI_MCA_odls_base_sigkill_timeout=0
# one node: the shared-memory transport (ob1 over vader), which Open MPI
# ends up with here anyway; naming it skips the cm layer's probing of
# fabric libraries (PSM, PSM2, OFI) this machine has no use for, 0.3 s of
# every launch (MPI_Init alone: 0.56 s against 0.23 s with mpirun -np 2);
# the suite launches geoblock over a thousand times. A caller's choice is kept.
export OMPI_MCA_pml=${OMPI_MCA_pml:-ob1}
logdir=build/test-logs
mkdir -p "$logdir" build/reports
rm -f build/reports/suites.tsv build/reports/verification.tsv
total_pass=0
total_fail=0
start=$(date +%s)
section=""
while read -r np prog args; do
  [ -z "${np:-}" ] && continue
  case "$np" in \#*) section="$prog${args:+ $args}"; continue ;; esac
  t0=$(date +%s)
  if [ "$np" = "script" ]; then VREPORT_SUITE=$(basename "$prog"); VREPORT_SUITE=${VREPORT_SUITE%.*}
  else VREPORT_SUITE="$prog-np$np"; fi
  export VREPORT_SUITE
  if [ "$np" = "script" ]; then
    name=$(basename "$prog"); name=${name%.*}
    log="$logdir/$name.log"
    case "$prog" in
      *.py) timeout 900 "${PYTHON:-/usr/bin/python3}" "$prog" $args > "$log" 2>&1 < /dev/null ;;
      *) timeout 900 bash "$prog" $args > "$log" 2>&1 < /dev/null ;;
    esac
    rc=$?
  else
    name="$prog-np$np"
    log="$logdir/$name.log"
    timeout 600 mpirun --oversubscribe -np "$np" "bin/tests/$prog" $args > "$log" 2>&1 < /dev/null
    rc=$?
  fi
  line=$(grep -E '^suite .*: [0-9]+ passed, [0-9]+ failed' "$log" | tail -n 1)
  if [ -n "$line" ]; then
    p=$(echo "$line" | sed -E 's/.*: ([0-9]+) passed, ([0-9]+) failed.*/\1/')
    f=$(echo "$line" | sed -E 's/.*: ([0-9]+) passed, ([0-9]+) failed.*/\2/')
    if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then f=1; fi
  else
    p=0; f=1
    line="suite $name: crashed or timed out (exit $rc), see $log"
  fi
  grep -E '^  FAIL' "$log" | sed "s/^/[$name]/"
  printf '%-40s %-28s %5d s\n' "$name" "${line#suite *: }" "$(( $(date +%s) - t0 ))"
  printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$section" "$name" "$p" "$f" "$(( $(date +%s) - t0 ))" \
    "$np $prog${args:+ $args}" >> build/reports/suites.tsv
  total_pass=$((total_pass + p))
  total_fail=$((total_fail + f))
done < tests/suites.txt
echo "test time: $(( $(date +%s) - start )) s"
"${PYTHON:-/usr/bin/python3}" tools/verification_report.py --command "make test" || \
  echo "warning: the verification report could not be written"
echo "$total_pass passed, $total_fail failed"
[ "$total_fail" -eq 0 ]
