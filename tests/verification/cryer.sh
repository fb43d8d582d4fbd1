#!/usr/bin/env bash
# Cryer's problem (three-field Biot on a sphere octant read from Gmsh files
# that meshes/make_sphere_octant.py writes here, levels 1, 2, 3: 56, 448 and
# 3584 hexahedra, R = 2 m): the normal load on the curved surface (an elastic
# sphere under a uniform radial stress: u = -S x / (3K) to round-off), the
# undrained step exact, the centre cell's pressure within 2% of p0 of the
# analytical centre pressure at every step (six times listed) and its
# Mandel-Cryer rise (level 3), 1 vs 2 ranks (level 2) to 1e-8, and the
# observed convergence orders of the pressure and the displacement (levels
# 1, 2, 3).
set -u
cd "$(dirname "$0")/../.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
PY=${PYTHON:-/usr/bin/python3}
out=build/test-out/cryer
rm -rf "$out"; mkdir -p "$out"
pass=0; fail=0
ok() { echo "  ok    $1"; pass=$((pass + 1)); }
ko() { echo "  FAIL  $1"; fail=$((fail + 1)); }
report() {  # name of the check, command...: one ok/FAIL line per line of its output, FAIL if it fails
  local what=$1 text rc line; shift
  text=$("$@" 2>&1); rc=$?
  while read -r line; do
    case "$line" in *FAIL*|*error:*|*Traceback*) ko "$what: $line" ;; *) ok "$what: $line" ;; esac
  done <<< "$text"
  if [ "$rc" -ne 0 ] && ! grep -qE 'FAIL|error:|Traceback' <<< "$text"; then ko "$what: exit status $rc"; fi
}
deck() {  # name, mesh level
  sed -e "s#sphere_octant_l3.msh#sphere_l$2.msh#" -e "s#build/test-out/cryer#$out/$1#" \
    tests/decks/cryer_test.nml > "$out/$1.nml"
}
run() {  # name, ranks
  timeout 600 mpirun --oversubscribe -np "$2" bin/geoblock "$out/$1.nml" > "$out/$1.log" 2>&1 < /dev/null
}
for level in 1 2 3; do
  $PY meshes/make_sphere_octant.py --level $level --radius 2 "$out/sphere_l$level.msh" > /dev/null \
    || ko "make_sphere_octant.py --level $level"
done
# the level 3 run (1 rank) goes on in the background while the small ones run
deck l3 3
run l3 1 &
l3_pid=$!

# 1. the normal load: an elastic octant under -1 MPa along the outward normals
cat > "$out/elastic.nml" <<EOF
&mesh
  source = 'gmsh', file = 'sphere_l2.msh'
/
&material
  region = 'sphere', young = 8.0e9, poisson = 0.15
/
&boundary
  set = 'xsym', type = 'displacement', ux = 0
/
&boundary
  set = 'ysym', type = 'displacement', uy = 0
/
&boundary
  set = 'zsym', type = 'displacement', uz = 0
/
&boundary
  set = 'outer', type = 'normal_traction', normal_traction = -1.0e6
/
&solver
  method = 'mumps'
/
&output
  dir = '$out/elastic', prefix = 'elastic'
/
EOF
if run elastic 1; then
  report "normal_traction on the sphere (elastic)" $PY - "$out/elastic" <<'PY'
import sys
sys.path.insert(0, "postproc")
import numpy as np
from geoblock_h5 import Run
r = Run(sys.argv[1], "elastic")
k = 8.0e9 / (3 * (1 - 2 * 0.15))
exact = -1.0e6 * r.coords / (3 * k)
err = np.max(np.abs(r.field("displacement", -1) - exact)) / np.max(np.abs(exact))
print(f"u = -S x/(3K) (uniform stress, exact for Q1 on the faceted sphere): max error {err:.2e} "
      f"of the surface displacement (tol 1e-10) {'ok' if err <= 1e-10 else 'FAIL'}")
PY
else
  ko "elastic run, see $out/elastic.log"
fi

# 2. levels 1 and 2 (1 rank), level 2 on 2 ranks: the same to round-off
for level in 1 2; do
  deck l$level $level
  run l$level 1 || ko "level $level run, see $out/l$level.log"
done
deck l2_np2 2
run l2_np2 2 || ko "level 2 run on 2 ranks, see $out/l2_np2.log"
if r=$($PY tests/invariance/compare_runs.py "$out/l2" "$out/l2_np2" cryer 1e-8 pressure displacement 2>&1); then
  ok "1 vs 2 ranks (level 2): $(echo "$r" | tail -2 | tr '\n' ' ')"
else
  ko "1 vs 2 ranks (level 2): $(echo "$r" | tr '\n' ' ')"
fi

# 3. level 3: undrained step, centre pressure, rise
if wait $l3_pid; then ok "level 3 run"; else ko "level 3 run, see $out/l3.log"; fi
report "level 3" $PY tests/verification/check_cryer.py "$out/l3" cryer --times 0.01,0.02,0.045,0.07,0.1,0.15

# 4. observed orders at t = 70 s (c t / R^2 = 0.1, the centre pressure
# falling from its peak), constant steps of 1 s on every mesh: against the
# implicit Euler series of the same steps (the spatial error alone)
while read -r line; do
  case "$line" in *FAIL*|*error:*) ko "$line" ;; *"observed orders"*) ok "$line" ;; *) echo "        $line" ;; esac
done < <($PY tests/verification/orders.py cryer 70 0.9 1.8 --min-pm 1.5 "$out/l1" "$out/l2" "$out/l3" 2>&1)
echo "suite cryer: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
