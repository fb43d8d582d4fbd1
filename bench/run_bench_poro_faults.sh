#!/usr/bin/env bash
# physics = 'poromechanics_faults' (issue 33, deliverable 2): FGMRES
# iterations per Newton iteration of its block preconditioner
# (src/physics/poro_faults_precon.f90) under refinement, against 'biot' and
# 'fracture_flow' on the same meshes, and its time against MUMPS.
# The case: tests/decks/poro_faults_states.nml (a fault with tips under
# compression and shear in a 1 m cube, a well at its centre, the matrix of
# permeability 1e-20 m^2 taking part of the fluid) on n^3 cells:
#   pf        poromechanics_faults, FGMRES: stick -> slip -> open
#   pf_stick  the same with a well 100 times weaker and friction 30 degrees
#             (every element sticks)
#   ff        fracture_flow on the same deck (no matrix fluid), FGMRES
#   biot      biot on the same mesh and loads without the fault, FGMRES
#   pf_mumps  poromechanics_faults with MUMPS (largest level only; steps 0
#             and 1 only: at 32^3 cells one factorization takes minutes,
#             so compare the times per Newton iteration)
# Per run: for every step its statuses and the FGMRES iterations of each
# Newton iteration (from the residual histories), set-up and solve seconds.
# Usage: bench/run_bench_poro_faults.sh [levels] [ranks] [t_end] [mumps level]
set -u
cd "$(dirname "$0")/.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
levels=${1:-"8 16 32"}
np=${2:-2}
t_end=${3:-4.0}
mumps_level=${4:-$(echo $levels | awk '{print $NF}')}
out=build/bench/poro_faults
mkdir -p "$out"
table=build/bench/poro_faults.md
echo "| cells per side | unknowns | case | per step: stick/slip/open, FGMRES its of each Newton iteration | largest | Newton iterations | setup [s] | solve [s] | total [s] | total per Newton iteration [s] | peak memory |" > "$table"
echo "|---|---|---|---|---|---|---|---|---|---|---|" >> "$table"
src=tests/decks/poro_faults_states.nml
deck() {  # name level -> $out/name_level.nml
  local name=$1 n=$2 f=$out/$1_$2.nml
  sed -e "s#dir = '[^']*'#dir = '$out/$1_$2'#" -e "s#nx = 8, ny = 8, nz = 8#nx = $n, ny = $n, nz = $n#" \
      -e "s#t_end = 4.0#t_end = $t_end#" -e "s#method = 'mumps'#method = 'fgmres'#" "$src" > "$f"
  case $name in
    pf_stick) sed -i -e "s#rate = 4.0e-9#rate = 4.0e-11#" -e "s#friction_angle = 10.0#friction_angle = 30.0#" "$f" ;;
    pf_mumps) sed -i -e "s#method = 'fgmres'#method = 'mumps'#" -e "s#t_end = $t_end#t_end = 1.0#" "$f" ;;
    ff) sed -i -e "s#physics = 'poromechanics_faults'#physics = 'fracture_flow'#" \
               -e "/permeability = 1.0e-20/d" "$f" ;;
    biot) sed -i -e "s#physics = 'poromechanics_faults'#physics = 'biot'#" -e "/^&fault/,/^\//d" \
                 -e "/^&well/,/^\//d" "$f" ;;
  esac
}
row() {  # name level
  local name=$1 n=$2 log=$out/$1_$2.log res=$out/$1_$2/states_residuals.csv
  local unknowns steps largest setup solve total
  unknowns=$(grep -m1 '^unknowns' "$log" | sed -E 's/^unknowns: //; s/ \(.*//')
  steps=$(/usr/bin/python3 - "$log" "$res" <<'PY'
import sys, csv, re, collections
log, res = sys.argv[1], sys.argv[2]
st = {}
for line in open(log):
    m = re.match(r"^(?:time )?step +(\d+)", line)
    if m:
        o = re.search(r"stick/slip/open ([0-9/]+)", line)
        st[m.group(1)] = o.group(1) if o else ""
its = collections.OrderedDict()
try:
    for r in csv.DictReader(open(res)):
        k = (r["step"].strip(), r["newton"].strip())
        its[k] = max(its.get(k, 0), int(r["iteration"]))
except FileNotFoundError:
    pass
per = collections.OrderedDict()
for (s, n), v in its.items():
    per.setdefault(s, []).append(v)
print("; ".join(f"{s}: {st.get(s, '')} {' '.join(map(str, v))}".replace(":  ", ": ") for s, v in per.items()))
print(max(its.values()) if its else "-")
PY
)
  largest=$(tail -1 <<< "$steps")
  steps=$(head -1 <<< "$steps")
  # Newton iterations over the steps (a linear step, biot's: one solve)
  newton=$(grep -E '^(time )?step +[0-9]' "$log" | awk '{ k = 1; for (i = 1; i < NF; i++) if ($i == "newton") k = $(i + 1); n += k } END { print n + 0 }')
  setup=$(awk '/^  preconditioner set-up/ {print $3}' "$log")
  solve=$(awk '/^  linear solve/ {print $3}' "$log")
  total=$(awk '/^  total/ {print $2}' "$log")
  per=$(awk -v t="$total" -v n="$newton" 'BEGIN { if (n > 0 && t != "") printf "%.2f", t / n; else print "-" }')
  peak=$(grep -m1 'peak resident memory' "$log" | sed -E 's/peak resident memory: //')
  echo "| $n | $unknowns | $name | $steps | $largest | $newton | $setup | $solve | $total | $per | ${peak:--} |" >> "$table"
}
for n in $levels; do
  cases="pf pf_stick ff biot"
  [ "$n" = "$mumps_level" ] && cases="$cases pf_mumps"
  for c in $cases; do
    deck "$c" "$n"
    mpirun --oversubscribe -np "$np" bin/geoblock "$out/${c}_$n.nml" > "$out/${c}_$n.log" 2>&1 < /dev/null
    row "$c" "$n"
    echo "level $n $c: $(tail -1 "$table" | cut -c1-200)"
  done
done
echo "table: $table"
