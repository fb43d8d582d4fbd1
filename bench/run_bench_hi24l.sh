#!/usr/bin/env bash
# The High Island 24L stand-in (issue 16; the seed's contact case with 32
# faults): input/hi24l.nml (a geostatic start, step 0 with the faults
# bonded, a 30 MPa depletion of the reservoir sands of the compartment
# between f02 and f06 in four load steps) on
# the meshes of meshes/hi24l.geo at the given refine factors (1: the full
# size, n_u 2,537,910, n_t 191,940; 0.5: medium; 0.1: small), FGMRES with the
# reordered contact preconditioner, 2 ranks by default.
# Per load step: stick/slip/open, Newton (active-set) iterations, the FGMRES
# count of every Newton iteration, set-up and solve seconds; per run the wall
# time and the peak memory (the log's timing summary and /usr/bin/time);
# then postproc/plot_faults.py draws the faults by status and by slip at the
# last step (build/bench/hi24l/<name>_status.png, _slip.png) and by status
# in the reservoir interval (_reservoir.png).
# Needs gmsh (installed with apt-get when missing) and numpy.
# Usage: bench/run_bench_hi24l.sh [refine factors] [ranks] [LIMIT seconds per run]
# Writes build/bench/hi24l.md.
set -u
cd "$(dirname "$0")/.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
refines=${1:-"0.5 1"}
np=${2:-2}
limit=${3:-0}
PY=${PYTHON:-/usr/bin/python3}
out=build/bench/hi24l
mkdir -p "$out"
table=build/bench/hi24l.md
if ! command -v gmsh > /dev/null; then
  echo "gmsh not found: installing it (apt-get install gmsh)"
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q gmsh > "$out/apt.log" 2>&1 || {
    echo "bench/run_bench_hi24l.sh: error: gmsh is needed to mesh meshes/hi24l.geo (see $out/apt.log)" >&2; exit 1; }
fi
{ echo "| refine | u / t unknowns | load step | stick/slip/open | Newton | FGMRES its per Newton iteration | set-up [s] | solve [s] |"
  echo "|---|---|---|---|---|---|---|---|"; } > "$table"
summary=""
for r in $refines; do
  name=hi24l_r$r
  msh=$out/$name.msh
  if [ ! -s "$msh" ]; then
    (cd meshes && gmsh -3 hi24l.geo -setnumber refine "$r" -o "../$msh" > "../$out/$name.gmsh.log" 2>&1) || {
      echo "| $r | (gmsh failed, see $out/$name.gmsh.log) | | | | | | |" >> "$table"; continue; }
    $PY meshes/make_hi24l.py --geo meshes/hi24l.geo "$msh" > "$out/$name.mesh.log" 2>&1 || {
      echo "| $r | (make_hi24l.py refused the mesh, see $out/$name.mesh.log) | | | | | | |" >> "$table"; continue; }
  fi
  sed -e "s#file = '../meshes/hi24l_full.msh'#file = '$PWD/$msh'#" \
      -e "s#dir = 'out', prefix = 'hi24l'#dir = '$out/$name', prefix = '$name'#" input/hi24l.nml > "$out/$name.nml"
  log=$out/$name.log
  t0=$(date +%s)
  if [ "$limit" -gt 0 ]; then
    /usr/bin/time -v timeout "$limit" mpirun --oversubscribe -np "$np" bin/geoblock "$out/$name.nml" > "$log" 2>&1
  else
    /usr/bin/time -v mpirun --oversubscribe -np "$np" bin/geoblock "$out/$name.nml" > "$log" 2>&1
  fi
  rc=$?
  wall=$(( $(date +%s) - t0 ))
  unk=$(grep -m1 '^unknowns:' "$out/$name/$name.log" 2>/dev/null | sed -E 's/unknowns: u ([0-9]+), t ([0-9]+).*/\1 \/ \2/')
  # the Newton lines of each load step, from the run's own log file
  awk -v r="$r" -v unk="$unk" '
    /^  newton +[0-9]+ +linear its/ { its = its (its == "" ? "" : " ") $5; next }
    /^load step [0-9]+\// {
      match($0, /stick\/slip\/open [0-9]+\/[0-9]+\/[0-9]+/); st = substr($0, RSTART + 16, RLENGTH - 16)
      match($0, /newton +[0-9]+/); nw = substr($0, RSTART + 6, RLENGTH - 6); gsub(/ /, "", nw)
      match($0, /setup +[0-9.]+/); su = substr($0, RSTART + 5, RLENGTH - 5); gsub(/ /, "", su)
      match($0, /solve +[0-9.]+/); so = substr($0, RSTART + 5, RLENGTH - 5); gsub(/ /, "", so)
      printf "| %s | %s | %s | %s | %s | %s | %s | %s |\n", r, unk, $3, st, nw, its, su, so
      its = ""
    }' "$out/$name/$name.log" >> "$table"
  peak=$(grep -m1 'peak resident memory' "$log" | sed -E 's/peak resident memory: //')
  rss=$(grep -m1 'Maximum resident set size' "$log" | awk '{printf "%.0f MB", $NF / 1024}')
  status="exit $rc"
  [ "$rc" -eq 0 ] && status="completed"
  [ "$limit" -gt 0 ] && [ "$rc" -eq 124 ] && status="stopped after $limit s"
  summary="$summary
- refine $r ($unk u / t unknowns): $status, wall ${wall} s; peak memory ${peak:-not reported} (largest process: ${rss:-?})"
  if [ -d "$out/$name" ]; then
    $PY postproc/plot_faults.py "$out/$name/$name" -o "$out/${name}_status.png" --elev 35 --azim -65 \
      > "$out/${name}_faults.txt" 2>&1
    $PY postproc/plot_faults.py "$out/$name/$name" --field slip_magnitude -o "$out/${name}_slip.png" --elev 35 \
      --azim -65 >> "$out/${name}_faults.txt" 2>&1
    # the reservoir interval (caprock to the underburden's top), drawn 6x
    # taller: where the depleted compartment's faults slip
    $PY postproc/plot_faults.py "$out/$name/$name" --z-range=-1500,-1900 --z-scale 6 --elev 35 --azim -70 \
      -o "$out/${name}_reservoir.png" >> "$out/${name}_faults.txt" 2>&1
  fi
done
echo "$summary" >> "$table"
cat "$table"
echo "table: $table"
