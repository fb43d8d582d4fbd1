#!/usr/bin/env bash
# &pressure_change (a given change of pore pressure, one-way coupled): a
# depleted layer in a laterally confined column compacts uniaxially. The
# two-layer Gmsh column (meshes/two_layers.msh: 'rock' below z = 0.6 with
# b = 0.8, 'cap' above), rollers on the sides and the base, a free top,
# dp = -10 MPa in the rock reached in two load steps: u_z = b dp z / M_rock
# in the rock (M = E (1 - nu) / ((1 + nu)(1 - 2 nu)), the oedometric
# modulus) and b dp 0.6 / M_rock above it, u_x = u_y = 0, at every node to
# 1e-9 of the top's (Q1 is exact for a displacement linear in each layer),
# the rock's effective stress b dp vertically and nu/(1-nu) b dp
# horizontally, the cap's zero (1e-9 of b |dp|); with the interface 'fault'
# between the layers as a contact fault (physics contact, 2 ranks): the same
# displacement, and every element's normal traction the fault pressure,
# the mean of the changes on its two sides (dp / 2: the total normal stress
# stays zero; the fault field 'pressure' says so), no shear, no opening;
# and a box-shaped reservoir's
# subsidence bowl against Geertsma's solution (below).
set -u
cd "$(dirname "$0")/../.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
PY=${PYTHON:-/usr/bin/python3}
out=build/test-out/pressure_change
rm -rf "$out"; mkdir -p "$out"
pass=0; fail=0
ok() { echo "  ok    $1"; pass=$((pass + 1)); }
ko() { echo "  FAIL  $1"; fail=$((fail + 1)); }
# rollers on the four sides (the base is held in each deck)
rollers="&boundary
  set = 'xmin', type = 'displacement', ux = 0.0
/
&boundary
  set = 'xmax', type = 'displacement', ux = 0.0
/
&boundary
  set = 'ymin', type = 'displacement', uy = 0.0
/
&boundary
  set = 'ymax', type = 'displacement', uy = 0.0
/"
deck() {  # name, physics, solver, extra groups
  cat > "$out/$1.nml" <<EOD
&run
  physics = '$2'
/
&mesh
  source = 'gmsh', file = '$PWD/meshes/two_layers.msh'
/
&material
  region = 'rock', young = 5.0e9, poisson = 0.3, biot = 0.8
/
&material
  region = 'cap', young = 2.0e10, poisson = 0.2
/
&pressure_change
  region = 'rock', value = -1.0e7
/
&boundary
  set = 'zmin', type = 'displacement', uz = 0.0
/
$rollers
&time
  n_steps = 2
/
&solver
  method = '$3', rtol = 1.0e-12
/
&output
  dir = '$out', prefix = '$1'
/
$4
EOD
}
check() {  # name, with fault (0|1)
  $PY - "$out/$1" "$2" <<'EOP'
import sys
import h5py
import numpy as np
path, fault = sys.argv[1], sys.argv[2] == "1"
mesh = h5py.File(path + "_mesh.h5", "r")
x, conn = mesh["coords"][:], mesh["connectivity"][:]
last = h5py.File(path + "_0001.h5", "r")
u, s = last["displacement"][:], last["stress"][:]
E, nu, b, dp = 5e9, 0.3, 0.8, -1e7
M = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu))
ue = b * dp / M * np.minimum(x[:, 2], 0.6)
eu = max(np.abs(u[:, 2] - ue).max(), np.abs(u[:, :2]).max()) / np.abs(ue).max()
zc = x[conn].mean(axis=1)[:, 2]
se = np.zeros_like(s)
rock = zc < 0.6
se[rock, 2] = b * dp
se[rock, 0] = se[rock, 1] = nu / (1 - nu) * b * dp
es = np.abs(s - se).max() / abs(b * dp)
bad = eu > 1e-9 or es > 1e-9
msg = f"displacement {eu:.1e} of the top's, stress {es:.1e} of b|dp| (tol 1e-9)"
if fault:
    fr = last["fractures"]
    tn, ts, op = fr["normal_traction"][:], fr["shear_traction"][:], fr["opening"][:]
    et = max(np.abs(tn - dp / 2).max(), np.abs(ts).max()) / abs(dp / 2)
    # the written fault pressure: the mean of the two cells' changes
    ep = np.abs(fr["pressure"][:] - dp / 2).max() / abs(dp / 2)
    bad = bad or et > 1e-9 or np.abs(op).max() > 1e-12 or ep > 1e-14
    msg += (f"; {len(tn)} fault elements: traction against dp/2 {et:.1e} (tol 1e-9), opening {np.abs(op).max():.1e} m"
            f", written pressure against dp/2 {ep:.1e} (tol 1e-14)")
print(("FAIL " if bad else "") + msg)
EOP
}
run_check() {  # name, ranks, with fault, what
  if ! timeout 300 mpirun --oversubscribe -np "$2" bin/geoblock "$out/$1.nml" > "$out/$1.out" 2>&1 < /dev/null; then
    ko "$4: the run failed, see $out/$1.out"; return
  fi
  r=$(check "$1" "$3" 2>&1)
  case "$r" in FAIL*|*Error*|*Traceback*) ko "$4: $r" ;; *) ok "$4: $r" ;; esac
}
deck column elasticity cg ""
run_check column 1 0 "depleted layer, elasticity, 1 rank"
deck column2 elasticity cg ""
run_check column2 2 0 "depleted layer, elasticity, 2 ranks"
deck fault contact fgmres "&fault
  name = 'fault', friction_angle = 30.0
/"
run_check fault 2 1 "depleted layer under a contact fault, 2 ranks"

# Geertsma: a 1 km x 1 km x 100 m reservoir at 1,000-1,100 m depth in a
# homogeneous half-space (quarter model, 8 x 8 km, 6 km deep, rollers on the
# sides, a fixed base), dp = -10 MPa: the surface displacement within 3.5 km
# against the nucleus-of-strain solution (check_geertsma.py), within 3% of
# the centre subsidence: measured 2.2% for u_z on this mesh (100 m cells
# near the reservoir, 13,824 cells) and 1.5% with 50 m cells (46,656): the
# 1.4% that stays is the box's rigid base and far sides, a shift of the
# whole bowl
cat > "$out/geertsma.nml" <<EOD
&mesh
  nx = 24, ny = 24, nz = 24
  lower = 0.0, 0.0, -6000.0, upper = 8000.0, 8000.0, 0.0
  core_n = 8, 8, 11
  core_lower = 0.0, 0.0, -1100.0, core_upper = 800.0, 800.0, 0.0
/
&region
  name = 'reservoir', lower = 0.0, 0.0, -1100.0, upper = 500.0, 500.0, -1000.0
/
&material
  region = 'domain', young = 1.0e10, poisson = 0.25
/
&material
  region = 'reservoir', young = 1.0e10, poisson = 0.25
/
&pressure_change
  region = 'reservoir', value = -1.0e7
/
$rollers
&boundary
  set = 'zmin', type = 'displacement', uz = 0.0
/
&solver
  method = 'cg', rtol = 1.0e-10
/
&output
  dir = '$out', prefix = 'geertsma'
/
EOD
if timeout 300 mpirun --oversubscribe -np 2 bin/geoblock "$out/geertsma.nml" > "$out/geertsma.out" 2>&1 < /dev/null; then
  r=$($PY tests/verification/check_geertsma.py "$out/geertsma" 1e10 0.25 -1e7 500 1000 1100 3500 0.03 2>&1)
  case "$r" in ok*) ok "Geertsma subsidence bowl: $r" ;; *) ko "Geertsma subsidence bowl: $r" ;; esac
else
  ko "Geertsma run failed, see $out/geertsma.out"
fi
echo "suite pressure_change: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
