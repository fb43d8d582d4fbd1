#!/usr/bin/env bash
# The program end to end: the Gmsh deck on 2 ranks against the oedometric
# solution, its output files and log; the matrix export of the cube deck
# (and the exported systems of flow_states.nml and poro_faults_states.nml with
# the PETSc peer);
# the stress components at ParaView's positions and the probe file.
set -u
cd "$(dirname "$0")/../.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
PY=${PYTHON:-/usr/bin/python3}
out=build/test-out/driver
rm -rf "$out"; mkdir -p "$out"
pass=0; fail=0
ok() { echo "  ok    $1"; pass=$((pass + 1)); }
ko() { echo "  FAIL  $1"; fail=$((fail + 1)); }

# 1. Gmsh mesh, two regions, oedometer
sed -e "s#dir = 'out'#dir = '$out/gmsh'#" -e "s#rtol = 1.0e-8#rtol = 1.0e-12#" -e "s#file = '../meshes/two_layers.msh'#file = '$PWD/meshes/two_layers.msh'#" input/gmsh_block.nml > "$out/gmsh.nml"
if timeout 300 mpirun --oversubscribe -np 2 bin/geoblock "$out/gmsh.nml" > "$out/gmsh.stdout" 2>&1 < /dev/null; then
  ok "gmsh_block deck runs on 2 ranks"
else
  ko "gmsh_block deck fails, see $out/gmsh.stdout"
fi
if r=$($PY tests/driver/check_oedometer.py "$out/gmsh" gmsh_block 2>&1); then ok "oedometer: $r"; else ko "oedometer: $r"; fi
# 1b. hypre's set-up statistics (&amg print_level = 1) on 2 ranks, as
# bench/run_bench_bandwidth.sh reads them: bench/solve_bytes.py's parse
# against hypre's own grid and operator complexities and the log's level line
sed -e "s#dir = 'out'.*#dir = '$out/amg_stats', fields = .false.#" -e "s#n_steps = 2 .*#n_steps = 1#" input/cube.nml > "$out/amg_stats.nml"
printf "&amg\n  print_level = 1\n/\n" >> "$out/amg_stats.nml"
if timeout 120 mpirun --oversubscribe -np 2 bin/geoblock "$out/amg_stats.nml" > "$out/amg_stats.stdout" 2>&1 < /dev/null \
   && r=$($PY bench/solve_bytes.py --check "$out/amg_stats.stdout" 2>&1) \
   && b=$($PY bench/solve_bytes.py "$out/amg_stats.stdout" 20 2>&1); then
  ok "hypre's set-up statistics parsed (bench/solve_bytes.py): $r; an iteration's cells: $b"
else
  ko "hypre's set-up statistics: ${r:-} ${b:-} (see $out/amg_stats.stdout)"
fi
[ -f "$out/gmsh/gmsh_block.xdmf" ] && ok "XDMF written" || ko "no XDMF"
[ -f "$out/gmsh/gmsh_block_0000.h5" ] && [ -f "$out/gmsh/gmsh_block_mesh.h5" ] && ok "HDF5 mesh and step files" \
  || ko "HDF5 files missing"
log="$out/gmsh/gmsh_block.log"
if [ -f "$log" ] && grep -q "strong_threshold *= 0.5 \[-\]" "$log" && grep -q "young *= .*\[Pa\]" "$log" && grep -q "^step 1/1" "$log" \
   && grep -q "timing summary" "$log" \
   && grep -Eq "^peak resident memory: [1-9][0-9]* MB on the largest rank, [1-9][0-9]* MB over all ranks$" "$log"; then
  ok "log file has the deck echo, the progress line, the timing summary and the peak memory"
else
  ko "log file incomplete: $log"
fi
grep -q "^step 1/1 .*iterations" "$out/gmsh.stdout" && ok "progress line on stdout" || ko "no progress line on stdout"
if r=$($PY tests/driver/check_timing.py "$log" "K: boomeramg" 2>&1); then ok "timing summary: set-up components, $r"; else ko "timing summary: $r"; fi

# 2. matrix export of a small cube
cat > "$out/export.nml" <<DECK
&mesh
  source = 'box', nx = 3, ny = 2, nz = 2
/
&material
  region = 'domain', young = 1.0e9, poisson = 0.3
/
&boundary
  set = 'xmin', type = 'displacement', ux = 0, uy = 0, uz = 0
/
&boundary
  set = 'xmax', type = 'traction', traction = 0, 0, -1.0e5
/
&output
  dir = '$out/export', prefix = 'cube', fields = .false., export_matrix = .true.
/
DECK
if timeout 120 mpirun --oversubscribe -np 2 bin/geoblock "$out/export.nml" > "$out/export.stdout" 2>&1 < /dev/null; then
  ok "export deck runs"
else
  ko "export deck fails, see $out/export.stdout"
fi
if r=$($PY - "$out/export/cube_K.mtx" "$out/export/cube_rhs.mtx" <<'PY' 2>&1
import sys
import numpy as np
rows = open(sys.argv[1]).read().split("\n")
assert rows[0].startswith("%%MatrixMarket matrix coordinate real general")
n, m, nnz = map(int, rows[2].split())
entries = np.array([list(map(float, r.split())) for r in rows[3:] if r.strip()])
assert n == m == 108 and len(entries) == nnz, (n, m, nnz, len(entries))
a = np.zeros((n, n))
a[entries[:, 0].astype(int) - 1, entries[:, 1].astype(int) - 1] = entries[:, 2]
assert np.allclose(a, a.T, rtol=0, atol=1e-9 * abs(a).max()), "not symmetric"
assert np.all(np.linalg.eigvalsh(a) > 0), "not positive definite"
b = np.loadtxt(sys.argv[2], comments="%", skiprows=3)
assert len(b) == n, len(b)
x = np.linalg.solve(a, b)
print(f"{n} x {m}, {nnz} non-zeros, symmetric positive definite, max |u| {abs(x).max():.3e}")
PY
); then ok "MatrixMarket export: $r"; else ko "MatrixMarket export: $r"; fi
grep -q "max |u| = " "$out/export.stdout" && ok "summary line" || ko "no summary line"
# 2b. &solver export_step: the u-t-p system of step 2, Newton iteration 2, of
# flow_states.nml as FGMRES sees it (D A D, D b), on 2 ranks; checked: the
# block sizes against the log's unknowns, the pressure entering the momentum
# rows as the normal traction does (A_up = -A_ut P, after undoing D), the
# pressure rows' positive diagonal, and that no other system was written
sed -e "s#dir = 'out'#dir = '$out/export_step'#" -e "s#method = 'mumps'#method = 'fgmres', export_step = 2, export_newton = 2#" \
  -e "s#t_end = 6.0#t_end = 3.0#" tests/decks/flow_states.nml > "$out/export_step.nml"
if timeout 300 mpirun --oversubscribe -np 2 bin/geoblock "$out/export_step.nml" > "$out/export_step.stdout" 2>&1 < /dev/null \
   && grep -q "step 2, Newton iteration 2: the linear system as the solver sees it written to" "$out/export_step.stdout"; then
  ok "export_step deck runs and logs the export"
else
  ko "export_step deck fails, see $out/export_step.stdout"
fi
if r=$($PY - "$out/export_step" "$out/export_step.stdout" <<'PY' 2>&1
import sys, glob, re
import numpy as np
d, log = sys.argv[1], open(sys.argv[2]).read()
files = sorted(glob.glob(d + "/*.mtx"))
base = d + "/flow_states_step2_newton2"
assert files == sorted(base + s for s in ["_K.mtx", "_rhs.mtx", "_scaling.mtx", "_fields.mtx"]), files
def array(path):
    rows = [r for r in open(path).read().split("\n") if r.strip() and not r.startswith("%")]
    return np.array([float(r) for r in rows[1:]])
head = open(base + "_fields.mtx").read().split("\n")
prefix = "% the block of every row of the exported matrix; blocks (1, 2, ...): "
assert head[2].startswith(prefix), head[2]
names = head[2][len(prefix):].split(",")
assert sorted(names) == ["p", "t", "u"], names     # t, p, u with the default pressure_block
f = np.array([names[i - 1] for i in array(base + "_fields.mtx").astype(int)])
dsc, b = array(base + "_scaling.mtx"), array(base + "_rhs.mtx")
rows = open(base + "_K.mtx").read().split("\n")
n, m, nnz = map(int, rows[2].split())
e = np.array([list(map(float, r.split())) for r in rows[3:] if r.strip()])
assert n == m == len(f) == len(b) == len(dsc) and len(e) == nnz, (n, m, len(f), len(e), nnz)
k = np.zeros((n, n)); k[e[:, 0].astype(int) - 1, e[:, 1].astype(int) - 1] = e[:, 2]
u_, t_, p_ = (int(x) for x in re.search(r"unknowns: u (\d+), t (\d+), p (\d+)", log).groups())
assert [np.sum(f == "u"), np.sum(f == "t"), np.sum(f == "p")] == [u_, t_, p_], (names, u_, t_, p_)
assert np.all(dsc > 0) and np.all(np.isfinite(b)) and np.linalg.norm(b) > 0
a = k / np.outer(dsc, dsc)                       # undo the scaling: A = D^-1 (D A D) D^-1
it, iu, ip = (np.where(f == j)[0] for j in ("t", "u", "p"))
q1 = a[np.ix_(iu, ip)]
c1n = a[np.ix_(iu, it[0::3])]                    # the normal traction's columns, element by element
res = np.abs(q1 + c1n).max() / np.abs(q1).max()
assert res < 1e-12, res
app = np.diag(a[np.ix_(ip, ip)])
assert np.all(app > 0), app.min()
x = np.linalg.solve(k, b)
print(f"{n} rows (blocks {','.join(names)}: t {t_}, u {u_}, p {p_}), max |A_up + A_ut P| / max |A_up| = {res:.1e}, "
      f"solvable (|D A D y - D b| = {np.linalg.norm(k @ x - b) / np.linalg.norm(b):.1e})")
PY
); then ok "export_step: $r"; else ko "export_step: $r"; fi
# 2b'. the PETSc peer of make bench (bench/peer_petsc.py: nested Schur
# fieldsplit, BoomerAMG and Jacobi on the blocks) on that exported system
if r=$($PY bench/peer_petsc.py --rtol 1e-10 "$out/export_step/flow_states_step2_newton2" 2>&1) \
   && grep -q "^petsc fieldsplit (t,p,u): converged, iterations [0-9]*, " <<< "$r"; then
  ok "PETSc fieldsplit peer on the exported u-t-p system: $r"
else
  ko "PETSc fieldsplit peer on the exported u-t-p system: $r"
fi
# 2b''. the same for poromechanics with faults (tests/decks/poro_faults_states.nml,
# step 3, Newton iteration 2, slipping): the blocks named in FGMRES's order
# t,u,q,pm,p with the log's sizes, and the PETSc peer with the two
# pressures in one split, as make bench runs it
sed -e "s#dir = '[^']*', prefix = 'states'#dir = '$out/export_poro', prefix = 'poro', fields = .false.#" \
  -e "s#method = 'mumps'#method = 'fgmres', export_step = 3, export_newton = 2#" -e "s#t_end = 4.0#t_end = 3.0#" \
  tests/decks/poro_faults_states.nml > "$out/export_poro.nml"
if timeout 300 mpirun --oversubscribe -np 2 bin/geoblock "$out/export_poro.nml" > "$out/export_poro.stdout" 2>&1 < /dev/null \
   && grep -q "step 3, Newton iteration 2 (exported): iterations" "$out/export_poro/poro.log"; then
  stem="$out/export_poro/poro_step3_newton2"
  blocks=$(sed -n 3p "${stem}_fields.mtx" | sed -E 's/.*: //')
  sizes=$(grep -m1 '^unknowns: ' "$out/export_poro/poro.log" | sed -E 's/unknowns: u ([0-9]+), q ([0-9]+), pm ([0-9]+), t ([0-9]+), p ([0-9]+).*/\4 \1 \2 \3 \5/')
  counts=$(awk 'NR > 4 {c[$1]++} END {printf "%d %d %d %d %d", c[1], c[2], c[3], c[4], c[5]}' "${stem}_fields.mtx")
  if [ "$blocks" = "t,u,q,pm,p" ] && [ "$sizes" = "$counts" ]; then
    ok "export_step, poromechanics with faults: blocks $blocks of $counts rows, as the log's unknowns"
  else
    ko "export_step, poromechanics with faults: blocks '$blocks' of '$counts' rows, the log's unknowns '$sizes'"
  fi
  if r=$($PY bench/peer_petsc.py "$stem" 2>&1) && grep -q "^petsc fieldsplit (t,u,q,pm+p): converged, iterations [0-9]*, " <<< "$r"; then
    ok "PETSc fieldsplit peer on the exported t-u-q-pm-p system: $r"
  else
    ko "PETSc fieldsplit peer on the exported t-u-q-pm-p system: $r"
  fi
else
  ko "export_step, poromechanics with faults: the run fails or exports nothing, see $out/export_poro.stdout"
fi
# 2c. export_step naming a step the run does not make: a warning at the end,
# no files, exit 0
sed -e "s#dir = '$out/export', prefix = 'cube', fields = .false., export_matrix = .true.#dir = '$out/export_none', prefix = 'cube', fields = .false.#" \
  "$out/export.nml" > "$out/export_none.nml"
printf "&solver\n  export_step = 7\n/\n" >> "$out/export_none.nml"
if timeout 120 mpirun --oversubscribe -np 2 bin/geoblock "$out/export_none.nml" > "$out/export_none.stdout" 2>&1 < /dev/null \
   && grep -q "warning: &solver export_step = 7, export_newton = 1: the run made no such linear system; nothing was exported" \
        "$out/export_none.stdout" && ! ls "$out/export_none"/*.mtx > /dev/null 2>&1; then
  ok "export_step beyond the run: a warning names it, nothing written, exit 0"
else
  ko "export_step beyond the run: no warning, files written or a failure, see $out/export_none.stdout"
fi
# 3. a fluid source in a sealed rigid box (biot, explicit step times): p = M rate t
if timeout 120 mpirun --oversubscribe -np 2 bin/geoblock tests/decks/source_test.nml > "$out/source.stdout" 2>&1 < /dev/null; then
  ok "source deck runs"
else
  ko "source deck fails, see $out/source.stdout"
fi
if r=$($PY - build/test-out/source <<'PY' 2>&1
import sys
sys.path.insert(0, "postproc")
import numpy as np
from geoblock_h5 import Run
r = Run(sys.argv[1], "source")
t = r.times()
assert np.allclose(t, [0, 1, 2, 4]), t
err = max(np.max(np.abs(r.field("pressure", i) - 1e9 * 1e-6 * t[i])) / 4e3 for i in range(len(t)))
print(f"times {list(t)}, max |p - M rate t| / p_end = {err:.2e}")
sys.exit(0 if err < 1e-10 else 1)
PY
); then ok "source: $r"; else ko "source: $r"; fi
# 4. output every n-th step: Mandel to t = 3 s (steps 0..25) with every = 10
sed -e "s#dir = 'out', prefix = 'mandel'#dir = '$out/every', prefix = 'mandel', every = 10#" -e "s#t_end = 200.0#t_end = 3.0#" \
  -e "s#history = 'mandel_plate.tab'#history = '$PWD/input/mandel_plate.tab'#" input/mandel.nml > "$out/every.nml"
timeout 120 mpirun --oversubscribe -np 2 bin/geoblock "$out/every.nml" > "$out/every.stdout" 2>&1 < /dev/null
nsteps=$(grep -c '^step' "$out/every.stdout")
nfiles=$(ls "$out/every"/mandel_[0-9]*.h5 2>/dev/null | wc -l)
last=$((nsteps - 1))
expect=$(( 2 + last / 10 ))
[ $((last % 10)) -ne 0 ] && expect=$((expect + 1))
if [ "$nfiles" -eq "$expect" ] && [ "$nsteps" -gt 10 ]; then
  ok "every = 10: $nsteps steps, $nfiles output files (steps 0, 1, multiples of 10, last)"
else
  ko "every = 10: $nsteps steps, $nfiles output files, expected $expect"
fi
# the smoother every physics defaults to, l1 Gauss-Seidel in geoblock's
# cycle on single-precision level values, in the parameters files of biot
# (Mandel) and elasticity (the gmsh deck)
for f in "$out/every/mandel_parameters.nml" "$out/gmsh/gmsh_block_parameters.nml"; do
  grep -q "^  relax_type *= 'l1-gs'" "$f" && grep -q "^  cycle_code *= 'geoblock'" "$f" && \
    grep -q "^  precision *= 'single'" "$f" && \
    ok "$(basename "$f"): &amg relax_type 'l1-gs', cycle_code 'geoblock', precision 'single' by default" \
    || ko "$(basename "$f"): &amg relax_type is not 'l1-gs', cycle_code not 'geoblock' or precision not 'single' by default"
done
# 5. the stress order ParaView labels (XX YY ZZ XY YZ XZ) on two exact
# constant-stress states, and the probe file of the triaxial box: against the
# exact solution, the field output, and 1 vs 2 ranks
for np in 1 2; do
  sed -e "s#dir = 'out'#dir = '$out/triaxial$np'#" tests/decks/triaxial_probes.nml > "$out/triaxial$np.nml"
  if timeout 120 mpirun --oversubscribe -np "$np" bin/geoblock "$out/triaxial$np.nml" > "$out/triaxial$np.stdout" 2>&1 \
     < /dev/null; then ok "triaxial box with probes runs on $np rank(s)"; else ko "triaxial box fails, see $out/triaxial$np.stdout"; fi
  if r=$($PY tests/driver/check_outputs.py probes "$out/triaxial$np" triaxial 2>&1); then ok "$np rank(s): $r"; else ko "$np rank(s): $r"; fi
done
if r=$($PY tests/driver/check_outputs.py stress "$out/triaxial2" triaxial triaxial 2>&1); then ok "$r"; else ko "$r"; fi
if r=$($PY tests/driver/check_outputs.py same_csv "$out/triaxial1/triaxial_probes.csv" "$out/triaxial2/triaxial_probes.csv" \
  1e-10 2>&1); then ok "probes, 1 vs 2 ranks: $r"; else ko "probes, 1 vs 2 ranks: $r"; fi
sed -e "s#dir = 'out'#dir = '$out/shear'#" tests/decks/shear_box.nml > "$out/shear.nml"
if timeout 120 mpirun --oversubscribe -np 2 bin/geoblock "$out/shear.nml" > "$out/shear.stdout" 2>&1 < /dev/null; then
  ok "sheared box runs"
else
  ko "sheared box fails, see $out/shear.stdout"
fi
if r=$($PY tests/driver/check_outputs.py stress "$out/shear" shear shear 2>&1); then ok "$r"; else ko "$r"; fi
echo "suite driver_outputs: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
