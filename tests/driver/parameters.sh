#!/usr/bin/env bash
# The resolved deck <prefix>_parameters.nml and the log: a run of it (another
# &output dir) reproduces the run bit for bit, for an elasticity, a Biot and
# a contact deck; the log file is written at verbosity 0, echoes values with
# units and no sentinel, and has the timing summary; --check prints a deck;
# the postproc scripts have --help, fail cleanly on a missing file and read
# a run's parameters.
set -u
cd "$(dirname "$0")/../.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
PY=${PYTHON:-/usr/bin/python3}
exe=bin/geoblock
out=build/test-out/parameters
rm -rf "$out"; mkdir -p "$out"
pass=0; fail=0
ok() { echo "  ok    $1"; pass=$((pass + 1)); }
ko() { echo "  FAIL  $1"; fail=$((fail + 1)); }

# run NAME DECK NP: run DECK with &output dir = $out/NAME/a (verbosity 0), then
# its _parameters.nml with dir = $out/NAME/b; compare the HDF5 outputs exactly
reproduce() {
  local name=$1 deck=$2 np=$3 a="$out/$1/a" b="$out/$1/b" prefix
  mkdir -p "$out/$name"
  # the deck with its own &output dir and verbosity 0 (groups &output/&run may be absent)
  sed -e "s#dir *= *'[^']*'#dir = '$a'#" -e "s/^ *verbosity *= *[0-9]//" "$deck" > "$out/$name/deck.nml"
  if ! grep -q '^&output' "$out/$name/deck.nml"; then
    printf "&output\n  dir = '%s'\n/\n" "$a" >> "$out/$name/deck.nml"
  elif ! grep -q "dir = '$a'" "$out/$name/deck.nml"; then
    sed -i "s#^&output#\&output\n  dir = '$a'#" "$out/$name/deck.nml"
  fi
  if grep -q '^&run' "$out/$name/deck.nml"; then
    sed -i "s#^&run#\&run\n  verbosity = 0#" "$out/$name/deck.nml"
  else
    printf "&run\n  verbosity = 0\n/\n" >> "$out/$name/deck.nml"
  fi
  if ! timeout 300 mpirun -np "$np" $exe "$out/$name/deck.nml" > "$out/$name/a.stdout" 2>&1 < /dev/null; then
    ko "$name: the deck fails, see $out/$name/a.stdout"; return 1
  fi
  [ -s "$out/$name/a.stdout" ] && ko "$name: verbosity 0 printed on the screen" || ok "$name: verbosity 0 is silent"
  prefix=$(ls "$a"/*_parameters.nml 2>/dev/null | head -1)
  if [ -z "$prefix" ]; then ko "$name: no _parameters.nml in $a"; return 1; fi
  ok "$name: $(basename "$prefix") written ($(grep -c ' = ' "$prefix") values)"
  prefix=$(basename "$prefix" _parameters.nml)
  log="$a/$prefix.log"
  if [ -f "$log" ] && grep -q "young *= .*\[Pa\]" "$log" && grep -q "timing summary" "$log" \
     && grep -q "^  assembly " "$log" && grep -q "^  preconditioner set-up " "$log" \
     && grep -Eq "^  (linear solve|factorization \(direct solver\)) " "$log"; then
    ok "$name: log file at verbosity 0 with the parameters and assembly / set-up / solve times"
  else
    ko "$name: log file $log incomplete"
  fi
  if grep -Eqi "e\+308|huge|1\.79769" "$log" "$a/${prefix}_parameters.nml"; then
    ko "$name: a sentinel value in the log or parameters: $(grep -Ehi 'e\+308|huge|1\.79769' "$log" | head -2)"
  else
    ok "$name: no sentinel value in the log and parameters"
  fi
  sed -e "s#^  dir  *= .*#  dir = '$b'#" "$a/${prefix}_parameters.nml" > "$out/$name/again.nml"
  if ! timeout 300 mpirun -np "$np" $exe "$out/$name/again.nml" > "$out/$name/b.stdout" 2>&1 < /dev/null; then
    ko "$name: the written deck fails, see $out/$name/b.stdout"; return 1
  fi
  if r=$($PY tools/compare_outputs.py "$a" "$b" --tol 0 2>&1 | tail -1) && [[ $r != *" 0 files"* ]]; then
    ok "$name: its _parameters.nml reproduces the run bit for bit ($r)"
  else
    ko "$name: the run of its _parameters.nml differs: $r"
  fi
}

reproduce elasticity input/cube.nml 2
sed -e "s/nz = 40/nz = 10/" -e "s/t_end = 200.0/t_end = 20.0/" tests/decks/terzaghi_test.nml > "$out/terzaghi_small.nml"
reproduce biot "$out/terzaghi_small.nml" 2
reproduce contact tests/decks/contact_stick.nml 1

# an elastic &amg with nodal coarsening and rigid-body modes: the Biot Schur
# complement's AMG takes the scalar copy without them (it failed at set-up
# with "nodal = 4 is not valid" before 2026-11-26), and the run agrees with
# the one of the default &amg (FGMRES to 1e-10: the fields to 1e-6)
for v in default nodal; do
  mkdir -p "$out/amg_$v"
  sed -e "s#method = 'mumps'#method = 'fgmres', rtol = 1.0e-10#" -e "s#build/test-out/terzaghi#$out/amg_$v#" \
    "$out/terzaghi_small.nml" > "$out/amg_$v.nml"
  [ $v = nodal ] && printf "&amg\n  nodal = 4, interp_vec_variant = 2\n/\n" >> "$out/amg_$v.nml"
  timeout 300 mpirun -np 2 $exe "$out/amg_$v.nml" > "$out/amg_$v.stdout" 2>&1 < /dev/null
  echo $? > "$out/amg_$v.rc"
done
if [ "$(cat "$out/amg_nodal.rc")" = 0 ] && [ "$(cat "$out/amg_default.rc")" = 0 ] && \
   r=$($PY tools/compare_outputs.py "$out/amg_default" "$out/amg_nodal" --tol 1e-6 2>&1 | tail -1); then
  ok "Biot with &amg nodal = 4, interp_vec_variant = 2: runs, the fields of the default &amg ($r)"
else
  ko "Biot with &amg nodal = 4, interp_vec_variant = 2: exit $(cat "$out/amg_nodal.rc"), $(tail -2 "$out/amg_nodal.stdout") ${r:-}"
fi

# --check prints the resolved deck, itself a valid deck
if $exe --check tests/decks/contact_stick.nml > "$out/check.nml" 2>&1 && \
   $exe --check "$out/check.nml" 2>&1 | grep -q "is valid (physics contact)"; then
  ok "--check prints a resolved deck that --check accepts"
else
  ko "--check output is not a valid deck: $out/check.nml"
fi

# postproc: --help everywhere, one clean line for a missing file
for s in postproc/*.py; do
  if $PY "$s" --help > "$out/help.txt" 2>&1 && grep -q "usage:" "$out/help.txt"; then ok "$s --help"
  else ko "$s --help"; fi
done
for s in plot_mandel plot_terzaghi plot_convergence; do
  msg=$($PY postproc/$s.py "$out/missing" run 2>&1); rc=$?
  if [ $rc -ne 0 ] && [ "$(wc -l <<< "$msg")" -eq 1 ] && [[ $msg == "$s.py: error:"* ]]; then
    ok "$s on a missing run: exit $rc, '$msg'"
  else
    ko "$s on a missing run: exit $rc, output: $(head -3 <<< "$msg")"
  fi
done
msg=$($PY postproc/plot_fracture.py "$out/missing/run" --case sneddon 2>&1); rc=$?
[ $rc -ne 0 ] && [ "$(wc -l <<< "$msg")" -eq 1 ] && ok "plot_fracture on a missing run: '$msg'" \
  || ko "plot_fracture on a missing run: $msg"
echo "not hdf5" > "$out/bad_mesh.h5"
msg=$($PY postproc/plot_terzaghi.py "$out" bad 2>&1); rc=$?
[ $rc -ne 0 ] && ! grep -q Traceback <<< "$msg" && ok "plot_terzaghi on an unreadable file: '$msg'" \
  || ko "plot_terzaghi on an unreadable file: $msg"
# the Terzaghi plot from the Biot run, its parameters read from terzaghi_parameters.nml
if r=$($PY postproc/plot_terzaghi.py "$out/biot/a" terzaghi "$out/terzaghi.png" 2>&1) && [ -s "$out/terzaghi.png" ]; then
  ok "plot_terzaghi on the Biot run (parameters from its _parameters.nml): $r"
else
  ko "plot_terzaghi on the Biot run: $r"
fi

echo "suite parameters: $pass passed, $fail failed"
[ $fail -eq 0 ]
