#!/usr/bin/env bash
# The tutorials (doc/tutorials/): their decks pass --check (check_docs.sh
# checks every deck too; here their runs' prerequisites), and the Mandel
# tutorial runs end to end as the page says: 2 ranks, the pressure against
# the analytical solution within 2 % of p0 at five times (the Mandel-Cryer
# rise included), the plot of the page and the probe file's columns.
set -u
cd "$(dirname "$0")/../.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
PY=${PYTHON:-/usr/bin/python3}
exe=${GEOBLOCK:-bin/geoblock}
out=build/test-out/tutorials
rm -rf "$out"; mkdir -p "$out"
pass=0; fail=0
ok() { echo "  ok    $1"; pass=$((pass + 1)); }
ko() { echo "  FAIL  $1"; fail=$((fail + 1)); }

for d in tutorial_mandel tutorial_fault tutorial_precon; do
  if timeout 60 "$exe" --check "input/$d.nml" > "$out/$d.check" 2>&1 < /dev/null; then
    ok "input/$d.nml passes --check"
  else
    ko "input/$d.nml: $(tail -1 "$out/$d.check")"
  fi
done

# the Mandel tutorial, its outputs in $out (the deck's input paths made absolute)
sed -e "s#dir = 'out'#dir = '$out'#" -e "s#history = 'mandel_plate.tab'#history = '$PWD/input/mandel_plate.tab'#" \
  input/tutorial_mandel.nml > "$out/tutorial_mandel.nml"
t0=$(date +%s)
if timeout 600 mpirun --oversubscribe -np 2 "$exe" "$out/tutorial_mandel.nml" > "$out/run.log" 2>&1 < /dev/null; then
  ok "input/tutorial_mandel.nml runs on 2 ranks ($(( $(date +%s) - t0 )) s, $(grep -c '^step' "$out/run.log") steps)"
else
  ko "input/tutorial_mandel.nml: $(tail -2 "$out/run.log" | tr '\n' ' ')"
fi
while read -r line; do
  case "$line" in *FAIL*|*error*) ko "analytical: $line" ;; *) ok "analytical: $line" ;; esac
done < <(VREPORT_TSV="$out/figures.tsv" $PY tests/verification/check_mandel.py "$out" tutorial_mandel 2>&1)
if $PY postproc/plot_mandel.py "$out" tutorial_mandel "$out/mandel.png" > "$out/plot.log" 2>&1 && [ -s "$out/mandel.png" ]; then
  ok "plot_mandel.py draws the page's figure"
else
  ko "plot_mandel.py: $(tail -1 "$out/plot.log")"
fi
head -1 "$out/tutorial_mandel_probes.csv" 2> /dev/null | grep -q 'centre:p \[Pa\]' && \
  head -1 "$out/tutorial_mandel_probes.csv" | grep -q 'plate:uy \[m\]' && \
  ok "the probe file has the page's columns: $(head -1 "$out/tutorial_mandel_probes.csv")" || \
  ko "the probe file's columns: $(head -1 "$out/tutorial_mandel_probes.csv" 2>&1)"

echo "suite tutorials: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
