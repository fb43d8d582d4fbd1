#!/usr/bin/env bash
# Draw the pictures of the manual (doc/images/*.png) from small runs of the
# tutorials' decks (make images; a few minutes on 2 ranks, not part of make
# test). Each deck runs with its outputs in build/images/ and its input
# paths made absolute; the pictures:
#   mesh_faults.png     the fault tutorial's Gmsh mesh with its fault (plot_mesh.py)
#   fault_slip.png      its fault after the depletion: slip, CFF, status (plot_fault_map.py)
#   pressure_field.png  Mandel's pressure at t = 10 s (plot_field.py)
#   mandel_pressure.png Mandel against the analytical solution (plot_mandel.py)
#   convergence.png     FGMRES with three Biot preconditioners on one system (plot_convergence.py --compare)
set -eu
cd "$(dirname "$0")/.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
PY=${PYTHON:-/usr/bin/python3}
NP=${NP:-2}
out=build/images
img=doc/images
mkdir -p "$out" "$img"
run() {  # name, source deck, extra sed expressions...: run the deck with its outputs in $out
  local name=$1 src=$2; shift 2
  sed -e "s#dir = 'out', prefix = '[a-z_]*'#dir = '$out', prefix = '$name'#" \
      -e "s#'\.\./meshes/#'$PWD/meshes/#" -e "s#history = 'mandel_plate.tab'#history = '$PWD/input/mandel_plate.tab'#" \
      "$@" "$src" > "$out/$name.nml"
  echo "== $name ($src)"
  mpirun -np "$NP" bin/geoblock "$out/$name.nml" > "$out/$name.stdout" 2>&1 || { tail "$out/$name.stdout"; exit 1; }
}

run fault input/tutorial_fault.nml
$PY postproc/plot_mesh.py "$out/fault" -o "$img/mesh_faults.png"
$PY postproc/plot_fault_map.py "$out/fault" -o "$img/fault_slip.png"

run mandel input/tutorial_mandel.nml
$PY postproc/plot_field.py "$out/mandel" --time 10 --scale 1e3 --unit kPa -o "$img/pressure_field.png"
$PY postproc/plot_mandel.py "$out" mandel "$img/mandel_pressure.png"

run precon_implicit input/tutorial_precon.nml
run precon_explicit_amg input/tutorial_precon.nml -e "s#decoupling = 'implicit', block_mode = 'ldu_cheap', schur = 'fixed_stress'#decoupling = 'explicit'#"
run precon_explicit_afsai input/tutorial_precon.nml \
  -e "s#decoupling = 'implicit', block_mode = 'ldu_cheap', schur = 'fixed_stress'#decoupling = 'explicit', restart = 300, max_iter = 5000#" \
  -e "s#k_precon = 'boomeramg', flux_precon = 'jacobi', schur_precon = 'boomeramg'#k_precon = 'afsai', flux_precon = 'afsai', schur_precon = 'afsai'#"
$PY postproc/plot_convergence.py --compare "$img/convergence.png" "$out/precon_implicit=implicit (default)" \
  "$out/precon_explicit_amg=explicit factors, AMG" "$out/precon_explicit_afsai=explicit aFSAI (the seed's)"
ls -l "$img"
