#!/usr/bin/env bash
# The pressure-controlled &source (pressure p_w, index I) against the
# steady closed form of a column (postproc/analytical.py SourceColumn;
# tests/verification/check_pressure_source.py states each check):
# 1. biot, m a = 2.12 (the source's layer resolved), MUMPS, 20, 40 and 80
#    cells: every cell's pressure and the source's rate within 1e-3 of the
#    closed form, second order; the outflow equals the source's rate to
#    1e-9 (nothing lost);
# 2. biot, a large index (I 1e-6, m a = 300: the source holds its cells at
#    p_w), 20 and 40 cells: the layer of width 1/m is below the cell and the
#    error first order. With its cells at p_w the source's top face sees the
#    consistent RT0 mass matrix's flux below it, -(2 - sqrt 3) Q, and the
#    column outside acts as if it were longer by h / (2 sqrt 3): the rate's
#    relative error is at most h / (2 sqrt 3 (L - a)) = 2.1e-2 at 20 cells
#    (measured 1.9e-2; the exact layer takes 1 / (m (L - a)) = 5e-4 off);
# 3. biot, a producer (p_w below the top's pressure), FGMRES with the block
#    preconditioner on 2 ranks against MUMPS on 1 (1e-8), and the closed
#    form; its name left out: the column 'source1:rate [m3/s]';
# 4. poromechanics_faults, the column cut at z = 6 by a closed, stuck fault
#    that passes the fluid (exchange 'open'): the same closed form in the
#    matrix and on the fault; FGMRES on 2 ranks against MUMPS on 1 (1e-6).
set -u
cd "$(dirname "$0")/../.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
. tests/common/vreport.sh
. tests/common/suite.sh
PY=${PYTHON:-/usr/bin/python3}
CHECK=tests/verification/check_pressure_source.py
out=build/test-out/pressure_source
rm -rf "$out"; mkdir -p "$out"
# run NAME RANKS: bin/geoblock on $out/NAME.nml (tests/common/suite.sh deck), its screen in $out/NAME.log
run() {
  if timeout 300 mpirun --oversubscribe -np "$2" bin/geoblock "$out/$1.nml" > "$out/$1.log" 2>&1 < /dev/null; then
    ok "run $1 ($2 rank(s))"
  else
    ko "run $1 ($2 rank(s)), see $out/$1.log"
  fi
}
check() { local what=$1; shift; local r rc; r=$($PY $CHECK "$@" 2>&1); rc=$?; lines $rc "$r" "$what"; }

D=tests/decks/pressure_source.nml
# 1. the resolved layer, three meshes
for n in 20 40 80; do
  deck col$n $D -e "s/nz = 20/nz = $n/"
  run col$n 1
  check "column $n" steady "$out/col$n/ps" --tol 1e-3 --balance 1e-9 --label "biot, injector"
done
check "orders" order "$out/col20/ps" "$out/col40/ps" --min-order 1.9 --label "biot, injector"
check "orders" order "$out/col40/ps" "$out/col80/ps" --min-order 1.9 --label "biot, injector"

# 2. a held source
for n in 20 40; do
  deck held$n $D -e "s/nz = 20/nz = $n/" -e "s/index = 5.0e-11/index = 1.0e-6/"
  run held$n 1
done
check "held 20" steady "$out/held20/ps" --tol 2.1e-2 --balance 1e-9 --label "biot, held source"
check "held 20 -> 40" order "$out/held20/ps" "$out/held40/ps" --min-order 0.95 --label "biot, held source"

# 3. a producer, 2 ranks FGMRES against 1 rank MUMPS
deck prod1 $D -e "s/pressure = 4.0e6/pressure = -2.0e6/" -e "s/name = 'inj', //"
deck prod2 "$out/prod1.nml" -e "s/method = 'mumps'/method = 'fgmres', precon = 'block', rtol = 1.0e-12/"
run prod1 1
run prod2 2
check "producer" steady "$out/prod1/ps" --tol 1e-3 --balance 1e-9 --label "biot, producer"
check "producer ranks" same "$out/prod1/ps" "$out/prod2/ps" --tol 1e-8 --label "biot, producer, FGMRES 2 ranks vs MUMPS 1"

# 4. poromechanics_faults
F=tests/decks/pressure_source_faults.nml
deck flt1 $F
deck flt2 $F -e "s/method = 'mumps'/method = 'fgmres', rtol = 1.0e-10/"
run flt1 1
run flt2 2
check "faults" steady "$out/flt1/psf" --tol 1e-3 --balance 1e-9 --label "poromechanics_faults, transparent fault"
check "faults ranks" same "$out/flt1/psf" "$out/flt2/psf" --tol 1e-6 \
  --label "poromechanics_faults, FGMRES 2 ranks vs MUMPS 1"

finish pressure_source
