#!/usr/bin/env bash
# Mandel's problem (three-field Biot, quarter model, displacement-controlled
# rigid plate): pressure at x = 0, a/2, 0.9a within 2% of the analytical
# solution at five times, the Mandel-Cryer rise, FGMRES + block
# preconditioner against MUMPS, 1 vs 2 ranks (MUMPS) to 1e-10.
set -u
cd "$(dirname "$0")/../.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
PY=${PYTHON:-/usr/bin/python3}
out=build/test-out/mandel
rm -rf "$out"; mkdir -p "$out"
pass=0; fail=0
ok() { echo "  ok    $1"; pass=$((pass + 1)); }
ko() { echo "  FAIL  $1"; fail=$((fail + 1)); }
deck() {  # name, sed expressions
  local name=$1; shift
  sed -e "s#dir = 'out'#dir = '$out/$name'#" -e "s#dt_max = 5.0#dt_max = 2.0#" -e "s#t_end = 200.0#t_end = 60.0#" \
      "$@" input/mandel.nml > "$out/$name.nml"
}
run() {
  timeout 600 mpirun --oversubscribe -np "$2" bin/geoblock "$out/$1.nml" > "$out/$1.log" 2>&1 < /dev/null
}
deck fgmres2 -e "s#rtol = 1.0e-8#rtol = 1.0e-12#"
if run fgmres2 2; then ok "FGMRES + block preconditioner run (2 ranks)"; else ko "FGMRES run, see $out/fgmres2.log"; fi
while read -r line; do
  case "$line" in *FAIL*) ko "$line" ;; *) ok "$line" ;; esac
done < <($PY tests/verification/check_mandel.py "$out/fgmres2" mandel 2>&1)
deck mumps1 -e "s#method = 'fgmres', precon = 'block', rtol = 1.0e-8#method = 'mumps'#"
deck mumps2 -e "s#method = 'fgmres', precon = 'block', rtol = 1.0e-8#method = 'mumps'#"
run mumps1 1 || ko "MUMPS run (1 rank)"
run mumps2 2 || ko "MUMPS run (2 ranks)"
if r=$($PY tests/invariance/compare_runs.py "$out/mumps1" "$out/mumps2" mandel 1e-10 pressure displacement 2>&1); then
  ok "1 vs 2 ranks: $(echo "$r" | tail -2 | tr '\n' ' ')"
else
  ko "1 vs 2 ranks: $(echo "$r" | tr '\n' ' ')"
fi
if r=$($PY tests/invariance/compare_runs.py "$out/mumps1" "$out/fgmres2" mandel 1e-8 pressure displacement 2>&1); then
  ok "FGMRES (rtol 1e-12) vs MUMPS: $(echo "$r" | tail -2 | tr '\n' ' ')"
else
  ko "FGMRES vs MUMPS: $(echo "$r" | tr '\n' ' ')"
fi
 for mode in ldu lower upper diagonal; do
  deck $mode -e "s#rtol = 1.0e-8#rtol = 1.0e-12, block_mode = '$mode'#" -e "s#t_end = 60.0#t_end = 5.0#"
  run $mode 2 || ko "block_mode = '$mode' run"
  if r=$($PY - "$out/mumps1" "$out/$mode" <<'PY' 2>&1
import sys
sys.path.insert(0, "postproc")
import numpy as np
from geoblock_h5 import Run, coordinate_order
a, b = Run(sys.argv[1], "mandel"), Run(sys.argv[2], "mandel")
ca, cb = coordinate_order(a.cell_centres()), coordinate_order(b.cell_centres())
n = len(b.steps)
err = max(np.max(np.abs(a.field("pressure", i)[ca] - b.field("pressure", i)[cb])) / np.max(np.abs(a.field("pressure", i)))
          for i in range(n - 1))
print(f"{n - 1} steps, pressure relative max difference to MUMPS {err:.2e} (tol 1e-8)")
sys.exit(0 if err < 1e-8 else 1)
PY
); then ok "block_mode = '$mode': $r"; else ko "block_mode = '$mode': $r"; fi
done
its=$(grep '^step' "$out/fgmres2.log" | sed -E 's/.*iterations +([0-9]+).*/\1/' | sort -n | tail -1)
echo "        most FGMRES iterations in a step (rtol 1e-12): $its"
echo "suite mandel: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
