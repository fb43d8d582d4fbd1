#!/usr/bin/env bash
# The peers of make bench on tiny systems, and the AMG options of the
# performance work (issue 15): hypre's MGR inside
# geoblock (&solver precon = 'mgr', mgr_precon.f90) on each block physics
# gives the same solution as our block preconditioners or MUMPS, and the
# log names it; an elastic deck refuses it. (The PETSc fieldsplit script is
# checked on an exported system in driver_outputs.sh.) BoomerAMG with the
# rigid-body modes in its interpolation (&amg interp_vec_variant) gives the
# same displacement as without.
set -u
cd "$(dirname "$0")/../.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
PY=${PYTHON:-/usr/bin/python3}
out=build/test-out/peers
rm -rf "$out"; mkdir -p "$out"
pass=0; fail=0
ok() { echo "  ok    $1"; pass=$((pass + 1)); }
ko() { echo "  FAIL  $1"; fail=$((fail + 1)); }
run() {  # deck, ranks
  if timeout 300 mpirun --oversubscribe -np "$2" bin/geoblock "$1" > "${1%.nml}.stdout" 2>&1 < /dev/null; then return 0; fi
  ko "run $1 on $2 ranks, see ${1%.nml}.stdout"
  return 1
}
its() { grep -E "$2" "$1" | sed -E "s/.*$3 +([0-9]+).*/\\1/" | paste -sd' '; }

# Biot: Mandel (input/mandel.nml on 12 x 12 x 1, five steps), block vs MGR
for pc in block mgr; do
  mkdir -p "$out/mandel_$pc"
  sed -e "s#nx = 20, ny = 20, nz = 1#nx = 12, ny = 12, nz = 1#" -e "s#t_end = 200.0#t_end = 0.2#" \
      -e "s#precon = 'block'#precon = '$pc'#" -e "s#dir = 'out', prefix = 'mandel'#dir = '$out/mandel_$pc', prefix = 'mandel'#" \
      -e "s#history = 'mandel_plate.tab'#history = '$PWD/input/mandel_plate.tab'#" input/mandel.nml > "$out/mandel_$pc.nml"
done
if run "$out/mandel_block.nml" 2 && run "$out/mandel_mgr.nml" 2; then
  grep -q "linear solver: fgmres + hypre's MGR on the whole system" "$out/mandel_mgr/mandel.log" \
    && ok "Biot with MGR: the log names it" || ko "Biot with MGR: the log does not name it"
  if r=$($PY tests/invariance/compare_runs.py "$out/mandel_block" "$out/mandel_mgr" mandel 1e-6 pressure displacement 2>&1); then
    ok "Biot (Mandel), MGR vs block preconditioner, pressure and displacement (1e-6); its $(its "$out/mandel_mgr/mandel.log" '^step ' iterations) against $(its "$out/mandel_block/mandel.log" '^step ' iterations)"
  else ko "Biot (Mandel), MGR vs block preconditioner: $r"; fi
  # the timing summary names each set-up component
  if r=$($PY tests/driver/check_timing.py "$out/mandel_block/mandel.log" "K: boomeramg" "A (flux): jacobi" \
       "Schur matrix (fixed_stress)" "Schur: boomeramg" 2>&1); then ok "Biot timing summary: $r"; else ko "Biot timing summary: $r"; fi
  if r=$($PY tests/driver/check_timing.py "$out/mandel_mgr/mandel.log" "hypre MGR" 2>&1); then ok "Biot with MGR, timing summary: $r"
  else ko "Biot with MGR, timing summary: $r"; fi
fi

# contact: the fault in a block (tests/decks/contact_block.nml), stick and slip
for pc in block mgr; do
  sed -e "s#method = 'mumps'#method = 'fgmres', rtol = 1.0e-10, precon = '$pc'#" -e "s#dir = 'out'#dir = '$out'#" \
      -e "s#prefix = 'contact_block'#prefix = 'contact_$pc'#" tests/decks/contact_block.nml > "$out/contact_$pc.nml"
done
if run "$out/contact_block.nml" 2 && run "$out/contact_mgr.nml" 2; then
  grep -q "linear solver: FGMRES with hypre's MGR on the whole system" "$out/contact_mgr.log" \
    && ok "contact with MGR: the log names it" || ko "contact with MGR: the log does not name it"
  if r=$($PY tests/verification/check_contact.py same "$out/contact_mgr" "$out/contact_block" 1e-6 2>&1); then
    ok "contact, MGR vs block preconditioner, jumps, tractions, statuses (1e-6); its $(its "$out/contact_mgr.log" '^  newton' 'linear its') against $(its "$out/contact_block.log" '^  newton' 'linear its')"
  else ko "contact, MGR vs block preconditioner: $(echo "$r" | tr '\n' ' ')"; fi
  if r=$($PY tests/driver/check_timing.py "$out/contact_block.log" "S*: product" "S*: boomeramg" 2>&1); then
    ok "contact timing summary: $r"; else ko "contact timing summary: $r"; fi
fi

# fracture flow: stick, slip and open (tests/decks/flow_states.nml), MGR vs MUMPS
sed -e "s#dir = 'out'#dir = '$out'#" -e "s#prefix = '[a-z_]*'#prefix = 'flow_mumps'#" tests/decks/flow_states.nml > "$out/flow_mumps.nml"
sed -e "s#dir = 'out'#dir = '$out'#" -e "s#prefix = '[a-z_]*'#prefix = 'flow_mgr'#" \
    -e "s#method = 'mumps'#method = 'fgmres', rtol = 1.0e-10, precon = 'mgr'#" tests/decks/flow_states.nml > "$out/flow_mgr.nml"
if run "$out/flow_mumps.nml" 2 && run "$out/flow_mgr.nml" 2; then
  grep -q "then p by Jacobi, u by BoomerAMG" "$out/flow_mgr.log" \
    && ok "fracture flow with MGR: the log names it" || ko "fracture flow with MGR: the log does not name it"
  if r=$($PY tests/verification/check_flow.py same "$out/flow_mgr" "$out/flow_mumps" 1e-6 2>&1); then
    ok "fracture flow, MGR vs MUMPS (1e-6): $r; its $(its "$out/flow_mgr.log" '^  newton' 'linear its')"
  else ko "fracture flow, MGR vs MUMPS: $r"; fi
fi
# poromechanics with faults: stick, slip and open (tests/decks/poro_faults_states.nml), MGR vs MUMPS
sed -e "s#dir = '[^']*'#dir = '$out/poro_mumps'#" tests/decks/poro_faults_states.nml > "$out/poro_mumps.nml"
sed -e "s#dir = '[^']*'#dir = '$out/poro_mgr'#" -e "s#method = 'mumps'#method = 'fgmres', rtol = 1.0e-10, precon = 'mgr'#" \
  tests/decks/poro_faults_states.nml > "$out/poro_mgr.nml"
if run "$out/poro_mumps.nml" 2 && run "$out/poro_mgr.nml" 2; then
  grep -q "then q by Jacobi, (pm, p) by BoomerAMG" "$out/poro_mgr/states.log" \
    && ok "poromechanics with faults with MGR: the log names it" || ko "poromechanics with faults with MGR: the log does not name it"
  if r=$(VREPORT_TSV="$out/vreport.tsv" $PY tests/verification/check_poro_faults_same.py "$out/poro_mumps/states" "$out/poro_mgr/states" 1e-6 \
       "poromechanics with faults, MGR vs MUMPS" 2>&1); then
    ok "poromechanics with faults, MGR vs MUMPS: $(tail -1 <<< "$r"); its $(its "$out/poro_mgr/states.log" '^  newton' 'linear its')"
  else ko "poromechanics with faults, MGR vs MUMPS: $(tr '\n' ' ' <<< "$r")"; fi
fi
# &contact reuse (the default): the Schur part kept while every element
# sticks; the same Jacobian, so bit for bit the fields of a rebuild at
# every Newton iteration (the onset case: 50 stick steps of closed fractures)
sed -e "s#dir = 'out'#dir = '$out'#" -e "s#prefix = '[a-z_]*'#prefix = 'onset_rebuild'#" \
    -e "s#t_end = [0-9.]*#t_end = 10.0#" -e "s#method = 'mumps'#method = 'fgmres', rtol = 1.0e-8#" tests/decks/flow_onset.nml > "$out/onset_rebuild.nml"
grep -q "^&contact" "$out/onset_rebuild.nml" && sed -i "s#^&contact#\&contact\n  reuse = .false.#" "$out/onset_rebuild.nml" \
  || printf "&contact\n  reuse = .false.\n/\n" >> "$out/onset_rebuild.nml"
sed -e "s#prefix = 'onset_rebuild'#prefix = 'onset_reuse'#" -e "/reuse = .false./d" "$out/onset_rebuild.nml" > "$out/onset_reuse.nml"
if run "$out/onset_rebuild.nml" 2 && run "$out/onset_reuse.nml" 2; then
  a=$(its "$out/onset_reuse.log" '^  newton' 'linear its'); b=$(its "$out/onset_rebuild.log" '^  newton' 'linear its')
  kept=$(grep -m1 "its Schur part kept at" "$out/onset_reuse.log" | sed -E 's/.*kept at ([0-9]+) .*/\1/')
  # every Newton iteration after the first of the step size dt = 1 (steps 0
  # and 1 build it) keeps it: all stick, one step size
  newton=$(grep -c '^  newton' "$out/onset_reuse.log")
  if r=$($PY tests/verification/check_flow.py same "$out/onset_reuse" "$out/onset_rebuild" 0 2>&1) && [ "$a" = "$b" ] \
     && [ "${kept:-0}" -ge $((newton - 2)) ] && [ "${kept:-0}" -ge 8 ] && ! grep -q "its Schur part kept" "$out/onset_rebuild.log"; then
    ok "&contact reuse: kept at $kept Newton iterations, the same fields bit for bit and the same counts as a rebuild at every one ($r)"
  else ko "&contact reuse differs from a rebuild: $r; counts $a against $b"; fi
fi

# BoomerAMG with the six rigid-body modes (GM, nodal coarsening) on a cube
for v in 0 2; do
  mkdir -p "$out/cube_$v"
  sed -e "s/nx = 16, ny = 16, nz = 16/nx = 12, ny = 12, nz = 12/" -e "s#dir = 'out'#dir = '$out/cube_$v'#" \
      -e "s#prefix = '[a-z_]*'#prefix = 'cube'#" input/cube.nml > "$out/cube_$v.nml"
done
printf "&amg\n  nodal = 4, interp_vec_variant = 2\n/\n" >> "$out/cube_2.nml"
if run "$out/cube_0.nml" 2 && run "$out/cube_2.nml" 2; then
  if r=$($PY tests/invariance/compare_runs.py "$out/cube_0" "$out/cube_2" cube 1e-6 displacement 2>&1); then
    ok "elasticity, BoomerAMG with the rigid-body modes (GM 2, nodal 4) vs without, displacement (1e-6); its $(its "$out/cube_2/cube.log" '^step ' iterations) against $(its "$out/cube_0/cube.log" '^step ' iterations)"
  else ko "elasticity with the rigid-body modes: $r"; fi
fi
echo "suite peers: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
