#!/usr/bin/env bash
# The field case (issue 33, deliverable 4): the High Island 24L stand-in
# produced from the compartment between f02 and f06 with the coupled flow
# (input/hi24l_coupled.nml, physics 'poromechanics_faults': a geostatic
# start, step 0 with the faults bonded, production by a sink in the
# compartment's sands), then the one-way run (input/hi24l.nml, physics
# 'contact') with the pressure the coupled run computed, as near as
# &pressure_change takes it: per sand, the coupled run's mean pressure
# change of the compartment's cells at each step, as a uniform change of
# that sand's compartment (value: the last step's mean; a history file
# with the earlier steps' share; one load step per coupled step).
# On the meshes of meshes/hi24l.geo at the given refine factor (0.1: the
# small mesh of git, meshes/hi24l_small.msh; others made with gmsh as
# bench/run_bench_hi24l.sh makes them), 2 ranks by default.
# Writes build/bench/field_coupled.md: per step of each run the Newton
# iterations, the linear iterations of each Newton iteration (MUMPS: 1),
# set-up and solve seconds; per run the wall time and the peak memory per
# rank (the log's 'peak resident memory' line and /usr/bin/time); per
# fault the step at which it first slips and its largest and mean slip
# over its slipping elements, in both runs; and the picture
# build/bench/field_coupled/field_r<refine>.png (postproc/field_coupled.py:
# the matrix's pressure change in the most depleted sand and the slip on the
# faults at the last step).
# Usage: bench/run_bench_field_coupled.sh [refine] [ranks] [solver: mumps | fgmres]
#   LIMIT=seconds stops a run after that long (default: no limit); REUSE=1
#   rewrites the report from the runs already there (no new run).
# The coupled run's solver: FGMRES with the block preconditioner as the
# deck sets it (without the fractures' subspace correction, as its figures
# were measured; doc/poromechanics_faults.md), or MUMPS.
set -u
cd "$(dirname "$0")/.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
r=${1:-0.1}
np=${2:-2}
solver=${3:-fgmres}
limit=${LIMIT:-0}
PY=${PYTHON:-/usr/bin/python3}
out=build/bench/field_coupled
mkdir -p "$out"
report=build/bench/field_coupled.md
points="6000,4000,-1580 6000,4000,-1690 6000,4000,-1810"   # the compartment, one point per sand

# the mesh
if [ "$r" = 0.1 ]; then
  msh=$PWD/meshes/hi24l_small.msh
else
  msh=$PWD/$out/hi24l_r$r.msh
  if [ ! -s "$msh" ]; then
    command -v gmsh > /dev/null || { echo "run_bench_field_coupled.sh: error: gmsh is needed for refine $r" >&2; exit 1; }
    (cd meshes && gmsh -3 hi24l.geo -setnumber refine "$r" -o "$msh" > "$msh.gmsh.log" 2>&1) &&
      $PY meshes/make_hi24l.py --geo meshes/hi24l.geo "$msh" > "$msh.make.log" 2>&1 ||
      { echo "run_bench_field_coupled.sh: error: meshing refine $r failed (see $msh.*.log)" >&2; exit 1; }
  fi
fi

# run NAME DECK: the run's wall time, exit status and peak memory
run() {
  local name=$1 deck=$2 t0 rc
  t0=$(date +%s)
  if [ "${REUSE:-0}" = 1 ] && [ -s "$out/$name.wall" ]; then
    rc=$(cut -d' ' -f2 "$out/$name.wall")
  else
    if [ "$limit" -gt 0 ]; then
      /usr/bin/time -v timeout "$limit" mpirun --oversubscribe -np "$np" bin/geoblock "$deck" > "$out/$name.out" 2>&1
    else
      /usr/bin/time -v mpirun --oversubscribe -np "$np" bin/geoblock "$deck" > "$out/$name.out" 2>&1
    fi
    rc=$?
  fi
  wall=$(( $(date +%s) - t0 ))
  if [ "${REUSE:-0}" = 1 ] && [ -s "$out/$name.wall" ]; then wall=$(cut -d' ' -f1 "$out/$name.wall"); fi
  echo "$wall $rc" > "$out/$name.wall"
  peak=$(grep -m1 'peak resident memory' "$out/$name.out" | sed -E 's/peak resident memory: //')
  rss=$(grep -m1 'Maximum resident set size' "$out/$name.out" | awk '{printf "%.0f MB", $NF / 1024}')
  status="exit $rc"
  [ "$rc" -eq 0 ] && status="completed"
  [ "$limit" -gt 0 ] && [ "$rc" -eq 124 ] && status="stopped after $limit s"
  echo "- $name: $status, wall ${wall} s, $np ranks; peak memory ${peak:-not reported} (largest process by /usr/bin/time: ${rss:-?})"
}

# steps LOG KIND: one table row per step (kind 'time' or 'load') with the
# linear iterations of each of its Newton iterations (a cut step's failed
# attempts are listed before the accepted one)
steps() {
  awk -v kind="$2" '
    /^  newton +[0-9]+ +linear its/ { its = its (its == "" ? "" : " ") $5; next }
    /no convergence at/ { its = its " (cut)"; next }
    ($0 ~ "^" kind " step [0-9]") {
      n = $3; sub(/\/.*/, "", n)
      match($0, /stick\/slip\/open [0-9]+\/[0-9]+\/[0-9]+/); st = substr($0, RSTART + 16, RLENGTH - 16)
      match($0, /newton +[0-9]+/); nw = substr($0, RSTART + 6, RLENGTH - 6); gsub(/ /, "", nw)
      t = ""; if (kind == "time") { match($0, / t +[0-9.E+-]+/); t = substr($0, RSTART + 3, RLENGTH - 3); gsub(/ /, "", t) }
      match($0, /setup +[0-9.]+/); su = substr($0, RSTART + 5, RLENGTH - 5); gsub(/ /, "", su)
      match($0, /solve +[0-9.]+/); so = substr($0, RSTART + 5, RLENGTH - 5); gsub(/ /, "", so)
      printf "| %s | %s | %s | %s | %s | %s | %s |\n", n, t, st, nw, its, su, so
      its = ""
    }' "$1"
}

# 1. the coupled run
name=coupled_r$r
sline="method = 'mumps'"
[ "$solver" = fgmres ] && sline="method = 'fgmres', rtol = 1.0e-8"
sed -e "s#file = '../meshes/hi24l_full.msh'#file = '$msh'#" \
    -e "s#method = 'fgmres', rtol = 1.0e-8#$sline#" \
    -e "s#dir = 'out', prefix = 'hi24l_coupled'#dir = '$out/$name', prefix = '$name'#" \
    input/hi24l_coupled.nml > "$out/$name.nml"
sum_c=$(run "$name" "$out/$name.nml")
stem_c=$out/$name/$name
log_c=$stem_c.log
unk_c=$(grep -m1 '^unknowns:' "$log_c" 2>/dev/null | sed -E 's/ \(.*//; s/unknowns: //')
times=$(grep -E '^time step [0-9]' "$log_c" | awk '$3 > 0 {printf "%s%s", (n++ ? "," : ""), $5}')

# 2. the one-way run with the coupled run's compartment pressures
$PY postproc/field_coupled.py compartment "$stem_c" $points -o "$out/$name.dp" > "$out/$name.dp.txt" || {
  echo "run_bench_field_coupled.sh: error: the coupled run wrote no output to compare (see $out/$name.out)" >&2
  cat "$out/$name.out" | tail -20 >&2; exit 1; }
nsteps=$(( $(grep -cE '^time step [0-9]' "$log_c") - 1 ))
oname=oneway_r$r
cp input/hi24l.nml "$out/$oname.nml"
sed -i -e "s#file = '../meshes/hi24l_full.msh'#file = '$msh'#" \
    -e "s#dir = 'out', prefix = 'hi24l'#dir = '$out/$oname', prefix = '$oname'#" \
    -e "s#^  n_steps = .*#  n_steps = $nsteps#" "$out/$oname.nml"
k=0
for s in sand_1 sand_2 sand_3; do
  k=$((k + 1))
  v=$(awk -v k=$k '$1 == k {print $2}' "$out/$name.dp.txt")
  sed -i -E "s#region = '$s', value = -3.0e7,#region = '$s', value = $v, history = '$PWD/$out/$name.dp_$k.tab',#" "$out/$oname.nml"
done
sum_o=$(run "$oname" "$out/$oname.nml")
stem_o=$out/$oname/$oname
unk_o=$(grep -m1 '^unknowns:' "$stem_o.log" 2>/dev/null | sed -E 's/ \(.*//; s/unknowns: //')

# 3. the picture and the report
png=$out/field_r$r.png
last=$(ls "$stem_c"_[0-9][0-9][0-9][0-9].h5 2>/dev/null | tail -1 | sed -E 's/.*_([0-9]{4})\.h5/\1/')
pic=$($PY postproc/field_coupled.py picture "$stem_c" "$((10#${last:-0}))" -o "$png" 2>&1) || pic="no picture: $pic"
{
  echo "## The field case: HI24L stand-in produced from a compartment, coupled against one-way"
  echo
  echo "refine $r (mesh $(basename "$msh")), $np ranks; coupled: input/hi24l_coupled.nml (poromechanics_faults," \
       "solver $solver; unknowns ${unk_c:-?}); one-way: input/hi24l.nml (contact, FGMRES; unknowns ${unk_o:-?})" \
       "with each sand's compartment mean pressure change of the coupled run as &pressure_change (value and history)."
  echo
  echo "$sum_c"
  echo "$sum_o"
  echo
  echo "Compartment mean pressure change per sand [Pa] (the one-way run's value, then the change at each step):"
  echo
  echo '```'
  cat "$out/$name.dp.txt"
  echo '```'
  echo
  echo "### Coupled run, per time step"
  echo
  echo "| step | t [s] | stick/slip/open | Newton | linear its per Newton iteration | set-up [s] | solve [s] |"
  echo "|---|---|---|---|---|---|---|"
  steps "$log_c" time
  echo
  echo "### One-way run, per load step"
  echo
  echo "| step | | stick/slip/open | Newton | FGMRES its per Newton iteration | set-up [s] | solve [s] |"
  echo "|---|---|---|---|---|---|---|"
  steps "$stem_o.log" load
  echo
  echo "### Faults that slip (elements with status slip; slip magnitude from step 0, max and mean over them)"
  echo
  $PY postproc/field_coupled.py faults "$stem_c" --label coupled --times "$times" | grep -v '^first'
  echo
  $PY postproc/field_coupled.py faults "$stem_o" --label one-way | grep -v '^first'
  echo
  echo "### Reactivation: first slipping step, and max / mean slip at the last step [m]"
  echo
  echo "| fault | coupled: first step | coupled: max | coupled: mean | one-way: first step | one-way: max | one-way: mean |"
  echo "|---|---|---|---|---|---|---|"
  $PY postproc/field_coupled.py faults "$stem_c" | grep '^first' > "$out/first_c.txt"
  $PY postproc/field_coupled.py faults "$stem_o" | grep '^first' > "$out/first_o.txt"
  join -a1 -a2 -e- -o 0,1.2,1.3,1.4,2.2,2.3,2.4 <(cut -d' ' -f2- "$out/first_c.txt" | sort) \
    <(cut -d' ' -f2- "$out/first_o.txt" | sort) | awk '{printf "| %s | %s | %s | %s | %s | %s | %s |\n", $1, $2, $3, $4, $5, $6, $7}'
  echo
  echo "$pic"
} > "$report"
cat "$report"
echo "table: $report"
