# Helpers of a shell suite. Source it after cd to the repository root:
#   ok TEXT / ko TEXT      one passed / failed check (counted in pass, fail)
#   lines RC OUTPUT WHAT   a Python checker's output lines as checks (a line
#                          with FAIL, a traceback or an error fails), and its
#                          exit status RC fails the suite too
#   deck NAME SOURCE [sed expressions]
#                          $out/NAME.nml: deck SOURCE edited, its output
#                          into $out/NAME ($out: the suite's directory)
#   finish NAME            the summary line; the suite's exit status
pass=0; fail=0
ok() { echo "  ok    $1"; pass=$((pass + 1)); }
ko() { echo "  FAIL  $1"; fail=$((fail + 1)); }
lines() {
  local rc=$1 r=$2 what=$3 line
  while read -r line; do
    [ -z "$line" ] && continue
    case "$line" in *FAIL*|*Traceback*|*rror:*) ko "$line" ;; *) ok "$line" ;; esac
  done <<< "$r"
  [ "$rc" -eq 0 ] || ko "$what checks (exit $rc)"
}
deck() { local n=$1 s=$2; shift 2; sed -e "s#dir = '[^']*'#dir = '$out/$n'#" "$@" "$s" > "$out/$n.nml"; }
finish() {
  echo "suite $1: $pass passed, $fail failed"
  [ "$fail" -eq 0 ]
}
