#!/usr/bin/env bash
# Geostatic start (&geostatic): the in-situ state of layered rock under
# gravity, its equilibrium step 0, and what later steps measure from it.
#  1. elasticity, the two-layer Gmsh column (meshes/two_layers.msh, 1 x 1 x 1
#     m, cap over rock), densities 2,500 / 2,300 kg/m^3, a water table
#     inside the cap, 0.1 MPa on the top, K0 = 0.7 in the rock and
#     nu / (1 - nu) in the cap, rollers on three sides only (x = 1 and the
#     top are held by the in-situ tractions): the log's imbalance is
#     round-off, the displacement zero and the stress at every cell centre
#     the lithostatic one (effective: sigma'_v = sigma_v + p0, K0 sigma'_v
#     horizontally) to 1e-9 of the largest, at every step, on 1 and 2 ranks;
#     the same with k0_max along N30E (an xy stress), 2 ranks;
#  2. superposition: the same column with 1 MPa more on the top in two load
#     steps gives the displacement of the run without gravity and the stress
#     of that run plus the in-situ stress (1e-7: both solved to 1e-10);
#  3. contact on the column's horizontal fault: every element's normal
#     traction is sigma'_v at the fault (1e-9), no shear, no slip;
#  4. contact on a fault dipping 30 degrees through a box, K0 = 0.5: the
#     tractions of step 0 are the in-situ traction at each element's centre
#     within a quarter of its change over the element (rho g dz: piecewise
#     constant tractions carry a traction linear along the dip), the
#     unloaded steps after it change nothing (slip below 1e-12 m); with a
#     friction angle of 10 degrees (the in-situ ratio |t_T| / |t_N| is
#     0.247, 13.9 degrees) the log names the fault's elements beyond the
#     Coulomb limit and step 1 slips;
#  5. a restart after step 2 of 3 of that run gives the continuous step 3;
#  6. Biot (b = 0.9 in the rock, a drained top): the column at rest keeps the
#     hydrostatic pressure (its change below 1e-9 of rho_f g H), zero
#     displacement and the lithostatic total stress (sigma_v vertically,
#     K0 (sigma_v + b p0) - b p0 horizontally, 1e-9); loaded, it equals the
#     dry run (displacement, pressure change) plus the in-situ state (1e-7).
# Bad decks of &geostatic are in tests/decks/bad_geostatic_*.nml.
set -u
cd "$(dirname "$0")/../.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
PY=${PYTHON:-/usr/bin/python3}
out=build/test-out/geostatic
rm -rf "$out"; mkdir -p "$out"
pass=0; fail=0
ok() { echo "  ok    $1"; pass=$((pass + 1)); }
ko() { echo "  FAIL  $1"; fail=$((fail + 1)); }
report() {  # name of the check, command...: one ok/FAIL line per line of its output
  local what=$1 text rc line; shift
  text=$("$@" 2>&1); rc=$?
  while read -r line; do
    case "$line" in *FAIL*|*error:*|*Traceback*) ko "$what: $line" ;; *) ok "$what: $line" ;; esac
  done <<< "$text"
  if [ "$rc" -ne 0 ] && ! grep -qE 'FAIL|error:|Traceback' <<< "$text"; then ko "$what: exit status $rc"; fi
}
run() {  # name, ranks
  if timeout 300 mpirun --oversubscribe -np "$2" bin/geoblock "$out/$1.nml" > "$out/$1.out" 2>&1 < /dev/null; then
    return 0
  fi
  ko "$1 ($2 ranks) did not run, see $out/$1.out"
  return 1
}
# rollers on the bottom and three sides (x = xmax is held by the in-situ tractions)
rollers="&boundary
  set = 'zmin', type = 'displacement', uz = 0.0
/
&boundary
  set = 'xmin', type = 'displacement', ux = 0.0
/
&boundary
  set = 'ymin', type = 'displacement', uy = 0.0
/
&boundary
  set = 'ymax', type = 'displacement', uy = 0.0
/"
column() {  # name, physics, geostatic (yes|no), extra groups
  local mats flow_rock='' flow_cap='' solver=cg
  [ "$2" = contact ] && solver=fgmres
  if [ "$2" = biot ]; then
    solver=fgmres
    flow_rock=", biot = 0.9, biot_modulus = 1.0e10, permeability = 1.0e-13"
    flow_cap=", permeability = 1.0e-15"
  fi
  if [ "$3" = yes ]; then
    mats="&material
  region = 'rock', young = 5.0e9, poisson = 0.3, density = 2300.0, k0 = 0.7$flow_rock
/
&material
  region = 'cap', young = 2.0e10, poisson = 0.2, density = 2500.0$flow_cap
/
&geostatic
  water_table = 0.8, surface_stress = 1.0e5
/"
  else
    mats="&material
  region = 'rock', young = 5.0e9, poisson = 0.3$flow_rock
/
&material
  region = 'cap', young = 2.0e10, poisson = 0.2$flow_cap
/"
  fi
  cat > "$out/$1.nml" <<EOF
&run
  physics = '$2'
/
&mesh
  source = 'gmsh', file = '$PWD/meshes/two_layers.msh'
/
$mats
$rollers
$4
&solver
  method = '$solver', rtol = 1.0e-10
/
&output
  dir = '$out', prefix = '$1'
/
EOF
}

# 1. the column at rest, 1 and 2 ranks
column rest elasticity yes "&time
  n_steps = 2
/"
for np in 1 2; do
  cp "$out/rest.nml" "$out/rest_np$np.nml"
  sed -i "s#prefix = 'rest'#prefix = 'rest_np$np'#" "$out/rest_np$np.nml"
  run rest_np$np $np && report "column at rest ($np ranks)" $PY tests/verification/check_geostatic.py column "$out/rest_np$np"
done

# 1b. the column at rest under horizontal stresses that differ with
# direction: k0_max along N30E in both layers (the stress has an xy part,
# which the in-situ tractions carry on the roller sides)
sed -e "s/density = 2300.0, k0 = 0.7/density = 2300.0, k0 = 0.6, k0_max = 1.4/" \
    -e "s/density = 2500.0/density = 2500.0, k0_max = 1.1/" \
    -e "s/water_table = 0.8, surface_stress = 1.0e5/water_table = 0.8, surface_stress = 1.0e5, sh_max_azimuth = 30.0/" \
    -e "s#prefix = 'rest'#prefix = 'aniso'#" "$out/rest.nml" > "$out/aniso.nml"
run aniso 2 && report "column at rest, k0_max along N30E (2 ranks)" \
  $PY tests/verification/check_geostatic.py column "$out/aniso"

# 2. superposition with a load on the top
load="&boundary
  set = 'zmax', type = 'traction', traction = 0.0, 0.0, -1.0e6
/
&time
  n_steps = 2
/"
column loaded elasticity yes "$load"
column dry elasticity no "$load"
run loaded 2 && run dry 2 && report "column loaded" $PY tests/verification/check_geostatic.py superposition "$out/loaded" "$out/dry"

# 3. contact on the horizontal fault
column fault contact yes "&fault
  name = 'fault', friction_angle = 30.0
/
&time
  n_steps = 1
/"
run fault 2 && report "horizontal fault" $PY tests/verification/check_geostatic.py flat_fault "$out/fault"

# 4. a dipping fault in a box
dipping() {  # name, friction angle
  cat > "$out/$1.nml" <<EOF
&run
  physics = 'contact'
/
&mesh
  nx = 12, ny = 3, nz = 12, upper = 12.0, 3.0, 12.0
/
&material
  region = 'domain', young = 1.0e10, poisson = 0.25, density = 2400.0, k0 = 0.5
/
&geostatic
  surface_stress = 2.0e6
/
$rollers
&fault
  name = 'f', normal_axis = 'z', position = 6.0, dip = 30.0, dip_axis = 'x', friction_angle = $2
/
&time
  n_steps = 2
/
&solver
  method = 'fgmres', rtol = 1.0e-10
/
&output
  dir = '$out', prefix = '$1'
/
EOF
}
dipping dip 30.0
run dip 2 && report "dipping fault" $PY tests/verification/check_geostatic.py dip_fault "$out/dip" 2.0e6 2400 0.5 12.0
dipping weak 10.0
if run weak 2; then
  if grep -q "geostatic: fault 'f': .* start beyond the Coulomb limit" "$out/weak.out"; then
    ok "friction 10 degrees: the log names the elements beyond the Coulomb limit"
  else
    ko "friction 10 degrees: no line on the elements beyond the Coulomb limit in $out/weak.out"
  fi
  slip=$(grep -m1 '^load step 1/2' "$out/weak.out" | sed -E 's/.*stick\/slip\/open ([0-9]+)\/([0-9]+)\/.*/\2/')
  if [ "${slip:-0}" -gt 0 ]; then ok "friction 10 degrees: step 1 slips ($slip elements)"
  else ko "friction 10 degrees: step 1 does not slip: $(grep -m1 '^load step 1/2' "$out/weak.out")"; fi
  # the post-processing picture of the reactivated fault (postproc/plot_faults.py)
  r=$($PY postproc/plot_faults.py "$out/weak" --step 1 -o "$out/weak_faults.png" 2>&1)
  if grep -q "fault          f:      36 elements, stick/slip/open 0/36/0" <<< "$r" && [ -s "$out/weak_faults.png" ]; then
    ok "plot_faults.py: $(head -1 <<< "$r" | sed 's/  */ /g')"
  else
    ko "plot_faults.py: $(tr '\n' ' ' <<< "$r")"
  fi
  if grep -q "start beyond the Coulomb limit" "$out/dip.out"; then ko "friction 30 degrees: elements said beyond the limit"
  else ok "friction 30 degrees: no element beyond the Coulomb limit"; fi
fi

# 6. Biot: the same column with flow (drained top, pressure changes from
# the hydrostatic one): at rest, and loaded against the dry run
biot_time="&boundary
  set = 'zmax', type = 'pressure', pressure = 0.0
/
&time
  dt = 1.0, t_end = 2.0
/"
column biot_rest biot yes "$biot_time"
run biot_rest 2 && report "Biot column at rest" $PY tests/verification/check_geostatic.py biot_column "$out/biot_rest"
column biot_loaded biot yes "$biot_time
&boundary
  set = 'zmax', type = 'traction', traction = 0.0, 0.0, -1.0e6
/"
column biot_dry biot no "$biot_time
&boundary
  set = 'zmax', type = 'traction', traction = 0.0, 0.0, -1.0e6
/"
run biot_loaded 2 && run biot_dry 2 && \
  report "Biot column loaded" $PY tests/verification/check_geostatic.py biot_superposition "$out/biot_loaded" "$out/biot_dry"

# 5. restart: a checkpoint after step 2 of 3 (the in-situ origin of the
# displacements and jumps goes with it) gives step 3 of the continuous run
sed -e "s#prefix = 'weak'#prefix = 'cont', checkpoint_every = 2#" -e 's/n_steps = 2/n_steps = 3/' "$out/weak.nml" > "$out/cont.nml"
if run cont 2; then
  cp "$out/cont_0003.h5" "$out/cont_full_0003.h5"
  sed "s#^&run#\&run\n  restart = '$out/cont_checkpoint.h5'#" "$out/cont.nml" > "$out/cont_restart.nml"
  if run cont_restart 2; then
    report "restart after step 2 of 3" $PY -c "
import h5py, numpy as np, sys
a, b = h5py.File('$out/cont_full_0003.h5', 'r'), h5py.File('$out/cont_0003.h5', 'r')
d = max(np.abs(a[k][:] - b[k][:]).max() / np.abs(a[k][:]).max() for k in
        ('displacement', 'stress', 'fractures/slip', 'fractures/normal_traction'))
print(('ok' if d <= 1e-12 else 'FAIL') + f': step 3 restarted against continuous: relative difference {d:.1e} (tol 1e-12)')
"
  fi
fi
echo "suite geostatic: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
