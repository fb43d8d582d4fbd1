#!/usr/bin/env bash
# Issue 33, deliverable 0: the physics 'contact' and 'fracture_flow' as
# compositions of components must give the results of the flagged
# contact_t they replace, to 1e-12 and with the same iteration counts.
# Runs a set of decks of both physics (MUMPS and FGMRES, the 'reordered',
# 'classical' and 'augmented' blocks, hypre's MGR, space 'bubble',
# &geostatic, &pressure_change, the fluid's 'schur' and 'eliminated'
# pressure blocks and its subspace correction, wells, &fracture_pressure;
# 1 and 2 ranks) with a reference binary and with this tree's
# bin/geoblock, and compares the two output trees case by case with
# tools/compare_outputs.py (every HDF5 dataset, the iteration counts of
# the logs), and the logs' text line by line (timings left out).
#
# usage: tests/regression/compare_components.sh REF_BINARY [NEW_BINARY] [CASE...]
#   REF_BINARY  e.g. /tmp/geoblock_ref_f6e, bin/geoblock built at f6e95cb
#   NEW_BINARY  default bin/geoblock
#   CASE        run only these cases (default: all)
# Not part of make test (it needs the reference binary). Prints one line per
# case and a summary; exits 1 when a case differs or fails to run.
set -u
cd "$(dirname "$0")/../.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
PY=${PYTHON:-/usr/bin/python3}
[ $# -ge 1 ] || { echo "usage: $0 REF_BINARY [NEW_BINARY] [CASE...]"; exit 2; }
REF=$(readlink -f "$1"); shift
NEW=$(readlink -f bin/geoblock)
if [ $# -ge 1 ] && [ -x "$1" ] && [ -f "$1" ]; then NEW=$(readlink -f "$1"); shift; fi
ONLY=("$@")
root=build/compare-components
rm -rf "$root"; mkdir -p "$root/ref" "$root/new"
n_same=0; n_diff=0

# a &contact or &fracture_flow setting: into the deck's group, or a new group
setting() {  # file, group, 'var = value'
  if grep -q "^&$2\b" "$1"; then
    sed -i "0,/^&$2\b/s##\&$2\n  $3#" "$1"
  else
    printf "&%s\n  %s\n/\n" "$2" "$3" >> "$1"
  fi
}

# case name, ranks, source deck, then sed expressions, then '--' and settings 'group:var = value'
case_() {
  local name=$1 np=$2 src=$3; shift 3
  local seds=() sets=() side dir f s
  while [ $# -gt 0 ] && [ "$1" != -- ]; do seds+=("$1"); shift; done
  [ $# -gt 0 ] && shift
  sets=("$@")
  if [ ${#ONLY[@]} -gt 0 ] && ! printf '%s\n' "${ONLY[@]}" | grep -qx "$name"; then return; fi
  for side in ref new; do
    dir=$root/$side/$name
    mkdir -p "$dir"
    cp tests/decks/nine_fractures_rate.tab "$dir/"
    cp -r tests/decks/histories "$dir/" 2>/dev/null
    f=$dir/$name.nml
    if [ "$src" = - ]; then cp "$root/$name.src" "$f"; else cp "$src" "$f"; fi
    sed -i -e "s#dir = '[^']*'#dir = '$dir'#" -e "s#prefix = '[A-Za-z0-9_]*'#prefix = '$name'#" "$f"
    grep -q "^&output" "$f" || printf "&output\n  dir = '%s', prefix = '%s'\n/\n" "$dir" "$name" >> "$f"
    grep -q "prefix = " "$f" || sed -i "s#dir = '$dir'#dir = '$dir', prefix = '$name'#" "$f"
    for s in ${seds[@]+"${seds[@]}"}; do sed -i -e "$s" "$f"; done
    for s in ${sets[@]+"${sets[@]}"}; do setting "$f" "${s%%:*}" "${s#*:}"; done
    local bin=$REF; [ "$side" = new ] && bin=$NEW
    if ! timeout 900 mpirun --oversubscribe -np "$np" "$bin" "$f" > "$dir/$name.stdout" 2>&1 < /dev/null; then
      echo "FAIL  $name ($np rank(s)): the $side run failed, see $dir/$name.stdout"
      n_diff=$((n_diff + 1)); return
    fi
  done
  local r rc logdiff
  r=$($PY tools/compare_outputs.py "$root/ref/$name" "$root/new/$name" --tol 1e-12 2>&1); rc=$?
  # the log text (timings and the timing table, dates, paths and the version line left out)
  logdiff=$(diff <(norm "$root/ref/$name/$name.log" ref) <(norm "$root/new/$name/$name.log" new) | grep -c '^[<>]')
  local maxrel its steps
  maxrel=$(maxrel "$root/ref/$name" "$root/new/$name")
  its=$(grep -E "^(load|time) step" "$root/new/$name/$name.log" | sed -E 's/.*newton +([0-9]+) +linear its +([0-9]+).*/\1:\2/' | \
        awk -F: '{n += $1; l += $2} END {printf "newton %d, linear its %d", n, l}')
  steps=$(grep -cE "^(load|time) step" "$root/new/$name/$name.log")
  if [ $rc -eq 0 ] && [ "$logdiff" -eq 0 ]; then
    echo "same  $name ($np rank(s)): $steps steps, $its (equal), max rel. diff $maxrel, log text equal"
    n_same=$((n_same + 1))
  else
    echo "DIFF  $name ($np rank(s)): max rel. diff $maxrel, $logdiff log lines differ; $(tail -1 <<< "$r")"
    grep -E '^(DIFF|only)' <<< "$r" | head -5 | sed 's/^/        /'
    n_diff=$((n_diff + 1))
  fi
}

# a log without what changes from run to run: times, dates, paths, versions
norm() {
  sed -E -e 's/ +[0-9]+\.[0-9]+ s\b/ T s/g' -e 's/(setup|solve|assembly|wall|time:) +[0-9.e+-]+/\1 T/g' \
         -e "s#$root/$2#ROOT#g" "$1" | grep -vE '^(geoblock|version|build|started|finished|date|host|  (set-up|timing|seconds))' | \
    grep -viE ' calls$|peak resident memory|seconds|wall time|[0-9]+\.[0-9]+ s( |$)|commit|version'
}

# largest relative difference over every real dataset of the two trees
maxrel() {
  $PY - "$1" "$2" <<'EOP'
import os, sys
import h5py
import numpy as np
a, b = sys.argv[1], sys.argv[2]
worst = 0.0
for base, _, names in os.walk(a):
    for n in names:
        if not n.endswith(".h5"):
            continue
        pa = os.path.join(base, n)
        pb = os.path.join(b, os.path.relpath(pa, a))
        if not os.path.exists(pb):
            continue
        with h5py.File(pa, "r") as fa, h5py.File(pb, "r") as fb:
            def visit(name, o):
                global worst
                if isinstance(o, h5py.Dataset) and name in fb and np.issubdtype(o.dtype, np.floating):
                    x, y = o[()], fb[name][()]
                    if np.shape(x) == np.shape(y) and np.size(x):
                        s = max(float(np.max(np.abs(x))), 1e-300)
                        worst = max(worst, float(np.max(np.abs(x - y))) / s)
            fa.visititems(visit)
print(f"{worst:.1e}")
EOP
}

MUMPS="s#method = 'mumps'#method = 'fgmres', rtol = 1.0e-10#"

# --- physics = 'contact' ---
case_ block_mumps1 1 tests/decks/contact_block.nml
case_ block_mumps2 2 tests/decks/contact_block.nml
case_ block_reordered 2 tests/decks/contact_block.nml "$MUMPS" -- "contact:block = 'reordered'"
case_ block_classical 2 tests/decks/contact_block.nml "$MUMPS" -- "contact:block = 'classical'"
case_ block_augmented 2 tests/decks/contact_block.nml "$MUMPS" -- "contact:block = 'augmented'"
case_ block_mgr 2 tests/decks/contact_block.nml "s#method = 'mumps'#method = 'fgmres', precon = 'mgr', rtol = 1.0e-10#"
case_ bubble_mumps2 2 tests/decks/contact_block.nml -- "contact:space = 'bubble'"
case_ bubble_augmented 2 tests/decks/contact_block.nml "$MUMPS" -- "contact:space = 'bubble'"
case_ stick_reordered 2 tests/decks/contact_stick.nml "s#method = 'mumps'#method = 'fgmres', rtol = 1.0e-12#"
case_ straight1 1 tests/decks/contact_straight_crack.nml
case_ sneddon2 2 input/sneddon.nml "s#nx = 110, ny = 80#nx = 80, ny = 60#" "s#core_n = 48, 10#core_n = 24, 6#"
case_ phan1 1 input/single_fracture.nml "s#nx = 72, ny = 98#nx = 66, ny = 78#" "s#core_n = 12, 38#core_n = 6, 18#"
case_ phan2 2 input/single_fracture.nml "s#nx = 72, ny = 98#nx = 66, ny = 78#" "s#core_n = 12, 38#core_n = 6, 18#"
case_ tutorial_fault2 2 input/tutorial_fault.nml "s#file = '../meshes/#file = '$PWD/meshes/#"
# &geostatic: the dipping fault of tests/verification/geostatic.sh, weak (it slips at step 1)
cat > "$root/geo_weak.src" <<'EOF'
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
&boundary
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
/
&fault
  name = 'f', normal_axis = 'z', position = 6.0, dip = 30.0, dip_axis = 'x', friction_angle = 10.0
/
&time
  n_steps = 2
/
&solver
  method = 'fgmres', rtol = 1.0e-10
/
&output
  dir = 'out', prefix = 'geo_weak'
/
EOF
case_ geo_weak 2 -
cp "$root/geo_weak.src" "$root/geo_weak_mumps.src"
case_ geo_weak_mumps 1 - "s#method = 'fgmres', rtol = 1.0e-10#method = 'mumps'#"
# &pressure_change under a contact fault (tests/verification/pressure_change.sh)
cat > "$root/pc_fault.src" <<EOF
&run
  physics = 'contact'
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
&boundary
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
/
&time
  n_steps = 2
/
&solver
  method = 'fgmres', rtol = 1.0e-12
/
&output
  dir = 'out', prefix = 'pc_fault'
/
&fault
  name = 'fault', friction_angle = 30.0
/
EOF
case_ pc_fault 2 -

# --- physics = 'fracture_flow' ---
case_ flow_nine2 2 tests/decks/flow_nine.nml
case_ flow_nine1 1 tests/decks/flow_nine.nml "s#t_end = 15.0#t_end = 10.0#"
case_ flow_nine_schur 2 tests/decks/flow_nine.nml "s#method = 'mumps'#method = 'fgmres', rtol = 1.0e-10, restart = 300#" \
  "s#t_end = 15.0#t_end = 10.0#" -- "fracture_flow:pressure_block = 'schur'"
case_ flow_nine_eliminated 2 tests/decks/flow_nine.nml "s#method = 'mumps'#method = 'fgmres', rtol = 1.0e-10, restart = 300#" \
  "s#t_end = 15.0#t_end = 10.0#" -- "fracture_flow:pressure_block = 'eliminated'"
case_ flow_closed_fine2 2 tests/decks/flow_closed_fine.nml
case_ flow_slip_front2 2 tests/decks/flow_slip_front.nml
case_ flow_injection2 2 tests/decks/flow_injection.nml "s#nx = 110, ny = 80#nx = 80, ny = 60#" "s#core_n = 48, 10#core_n = 24, 6#"
case_ flow_penny2 2 tests/decks/flow_penny.nml "s#nx = 28, ny = 28#nx = 17, ny = 17#" "s#core_n = 18, 18, 2#core_n = 9, 9, 2#"
case_ flow_split1 1 tests/decks/flow_split.nml
case_ flow_split_fgmres 2 tests/decks/flow_split.nml "$MUMPS"
case_ flow_steady2 2 tests/decks/flow_steady.nml
case_ flow_onset2 2 tests/decks/flow_onset.nml
case_ flow_states_mumps 2 tests/decks/flow_states.nml
case_ flow_states_jacobi 2 tests/decks/flow_states.nml "$MUMPS" -- \
  "fracture_flow:pressure_block = 'schur', pressure_precon = 'jacobi', subspace_correction = .false."
case_ flow_states_pcg 2 tests/decks/flow_states.nml "$MUMPS" -- "fracture_flow:pressure_block = 'eliminated'" \
  "contact:schur_solve = 'pcg'"
case_ flow_states_mgr 2 tests/decks/flow_states.nml "s#method = 'mumps'#method = 'fgmres', precon = 'mgr', rtol = 1.0e-10#"

echo "compare_components: $n_same cases the same, $n_diff differ or failed (reference $REF, new $NEW)"
[ "$n_diff" -eq 0 ]
