# The verification report's rows (make test writes build/reports/verification.md
# from them, tools/verification_report.py). Source this file in a suite, then
#   vreport CASE QUANTITY ERROR TOLERANCE ORDER RESULT
# appends one row: the case (a problem and its mesh), the quantity compared,
# the measured error, the tolerance it is held to, an observed convergence
# order ('' when none) and 'pass' or 'FAIL'. Python checkers use
# tests/common/vreport.py, test programs assertions' report.
export VREPORT_SUITE=${VREPORT_SUITE:-$(basename "$0" .sh)}
vreport() {
  local f=${VREPORT_TSV:-build/reports/verification.tsv}
  mkdir -p "$(dirname "$f")"
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$VREPORT_SUITE" "$1" "$2" "$3" "$4" "$5" "$6" >> "$f"
}
# vcheck CASE QUANTITY ERROR TOLERANCE [ORDER]: error <= tolerance decides
# (both numbers), then vreport and the suite's ok / ko (which it must define)
vcheck() {
  local r=FAIL
  if awk -v e="$3" -v t="$4" 'BEGIN { exit !(e + 0 <= t + 0) }'; then r=pass; fi
  vreport "$1" "$2" "$3" "$4" "${5:-}" "$r"
  if [ "$r" = pass ]; then ok "$1: $2 $3 (tol $4)"; else ko "$1: $2 $3 > $4"; fi
}
