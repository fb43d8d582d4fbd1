#!/usr/bin/env bash
# Boundary conditions on part of a set (&boundary lower, upper), on a box
# [0,2] x [0,2] x [0,1] of 4 x 4 x 2 cells clamped at zmin:
#  1. surface loads: a traction (0, 0, -1 MPa) on the half x <= 1 of zmax and
#     a normal traction of -2 MPa on its quarter x, y >= 1: the assembled
#     load vector (export_matrix, 1 rank) sums to -1e6 x 2 m^2 - 2e6 x 1 m^2
#     = -4e6 N in z, and no load reaches the top nodes of the quarter
#     x > 1, y < 1 that neither box selects;
#  2. a displacement uz = -1 cm on the faces of zmax with x <= 1 only, on 1
#     and 2 ranks: the nodes of those faces move by -1 cm, the others not,
#     the same fields on both rank counts (a ghost node's flag comes from
#     its owner);
#  3. Biot: an outward flux of 1e-7 m/s through the half x <= 1 of zmax for
#     one step of 10 s (incompressible constituents, every other face
#     impermeable, free top): the volume change, the integral of u_z over
#     the top, equals -dt x flux x 2 m^2 = -2e-6 m^3 (mass balance summed
#     over the cells; MUMPS), on 1 and 2 ranks.
# The pressure and normal_traction types take the same face filter as flux
# and traction.
set -u
cd "$(dirname "$0")/../.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
PY=${PYTHON:-/usr/bin/python3}
out=build/test-out/partial_loads
rm -rf "$out"; mkdir -p "$out"
pass=0; fail=0
ok() { echo "  ok    $1"; pass=$((pass + 1)); }
ko() { echo "  FAIL  $1"; fail=$((fail + 1)); }
run() {   # run NAME RANKS
  if timeout 120 mpirun --oversubscribe -np "$2" bin/geoblock "$out/$1.nml" > "$out/$1_np$2.stdout" 2>&1 < /dev/null; then
    return 0
  fi
  ko "$1 on $2 rank(s) fails, see $out/$1_np$2.stdout"; return 1
}
per_rank() {   # per_rank NAME RANKS: deck NAME with its output in NAME_npRANKS, run
  sed "s#dir = '$out/$1'#dir = '$out/$1_np$2'#" "$out/$1.nml" > "$out/$1_np$2.nml"
  run "$1_np$2" "$2"
}
head() {   # head PHYSICS: the box, clamped at zmin
  printf "&run\n  physics = '%s'\n/\n&mesh\n  source = 'box', nx = 4, ny = 4, nz = 2, upper = 2, 2, 1\n/\n" "$1"
  printf "&boundary\n  set = 'zmin', type = 'displacement', ux = 0, uy = 0, uz = 0\n/\n"
}

# 1. loads
{ head elasticity
  cat <<DECK
&material
  region = 'domain', young = 1.0e9, poisson = 0.3
/
&boundary
  set = 'zmax', type = 'traction', traction = 0, 0, -1.0e6, upper(1) = 1
/
&boundary
  set = 'zmax', type = 'normal_traction', normal_traction = -2.0e6, lower = 1, 1, 0
/
&output
  dir = '$out/loads', prefix = 'box', fields = .false., export_matrix = .true.
/
DECK
} > "$out/loads.nml"
if run loads 1; then
  if r=$($PY - "$out/loads/box_rhs.mtx" <<'PY' 2>&1
import sys
import numpy as np
b = np.loadtxt(sys.argv[1], comments="%", skiprows=3)
fz = b[2::3]                        # dofs interleaved per node, nodes in box order (1 rank)
i, j, k = np.meshgrid(np.arange(5), np.arange(5), np.arange(3), indexing="ij")
x, y, z = (i * 0.5).ravel("F"), (j * 0.5).ravel("F"), (k * 0.5).ravel("F")
total = fz.sum()
assert abs(total + 4.0e6) < 1e-6 * 4.0e6, total
free = (z == 1) & (x > 1.01) & (y < 0.99)
assert np.all(fz[free] == 0), fz[free]
assert np.all(abs(b[0::3]) + abs(b[1::3]) == 0)
print(f"sum of the z loads {total:.6e} N (exact -4e6), none on the {free.sum()} top nodes outside both boxes")
PY
  ); then ok "traction and normal traction on parts of zmax: $r"; else ko "loads: $r"; fi
fi

# 2. displacement on part of a set
{ head elasticity
  cat <<DECK
&material
  region = 'domain', young = 1.0e9, poisson = 0.3
/
&boundary
  set = 'zmax', type = 'displacement', uz = -0.01, upper(1) = 1
/
&solver
  method = 'cg', precon = 'boomeramg', rtol = 1.0e-12
/
&output
  dir = '$out/disp', prefix = 'box'
/
DECK
} > "$out/disp.nml"
per_rank disp 1; per_rank disp 2
if r=$($PY - "$out/disp_np1" "$out/disp_np2" <<'PY' 2>&1
import sys
import numpy as np, h5py
res = []
for d in sys.argv[1:]:
    with h5py.File(f"{d}/box_mesh.h5") as m:
        xyz = m["coords"][()]
    with h5py.File(f"{d}/box_0000.h5") as f:
        u = f["displacement"][()]
    key = np.lexsort(xyz.T)
    xyz, u = xyz[key], u[key]
    top = np.isclose(xyz[:, 2], 1.0)
    held = top & (xyz[:, 0] <= 1 + 1e-12)
    assert np.all(abs(u[held, 2] + 0.01) < 1e-14), u[held, 2] + 0.01
    rest = top & ~held
    assert np.all(abs(u[rest, 2] + 0.01) > 1e-4), u[rest, 2]
    res.append(u)
diff = abs(res[0] - res[1]).max() / abs(res[0]).max()
assert diff < 1e-9, diff          # CG to 1e-12 on both rank counts
print(f"{held.sum()} top nodes held at -1 cm, the other {rest.sum()} free (uz {u[rest, 2].min():.4f} to {u[rest, 2].max():.4f}); 1 vs 2 ranks {diff:.1e}")
PY
); then ok "displacement on part of zmax: $r"; else ko "displacement on part of zmax: $r"; fi

# 3. Biot flux on part of a set
{ head biot
  cat <<DECK
$(for bc in "xmin ux = 0" "xmax ux = 0" "ymin uy = 0" "ymax uy = 0"; do
  printf "&boundary\n  set = '%s', type = 'displacement', %s\n/\n" "${bc%% *}" "${bc#* }"; done)
&material
  region = 'domain', young = 1.0e8, poisson = 0.25, permeability = 1.0e-12
/
&boundary
  set = 'zmax', type = 'flux', flux = 1.0e-7, upper(1) = 1
/
&time
  dt = 10.0, t_end = 10.0, undrained = .false.
/
&solver
  method = 'mumps'
/
&output
  dir = '$out/flux', prefix = 'box'
/
DECK
} > "$out/flux.nml"
for np in 1 2; do
  per_rank flux "$np" || continue
  if r=$($PY - "$out/flux_np$np" <<'PY' 2>&1
import sys
import numpy as np, h5py
d = sys.argv[1]
with h5py.File(f"{d}/box_mesh.h5") as m:
    xyz = m["coords"][()]
    conn = m["connectivity"][()]
with h5py.File(f"{d}/box_0000.h5") as f:
    u = f["displacement"][()]
vol = 0.0
for q in range(conn.shape[0]):                     # top faces: nodes 4..7 of the cells at the top
    nodes = conn[q, 4:]
    if np.allclose(xyz[nodes, 2], 1.0):
        vol += u[nodes, 2].mean() * 0.25           # bilinear u_z over a 0.5 x 0.5 face
exact = -10.0 * 1.0e-7 * 2.0
assert abs(vol - exact) < 1e-9 * abs(exact), (vol, exact)
print(f"volume change {vol:.9e} m^3, exact {exact:.3e} (relative {abs(vol / exact - 1):.1e})")
PY
  ); then ok "Biot flux on half of zmax, $np rank(s): $r"; else ko "Biot flux, $np rank(s): $r"; fi
done
echo "suite partial_loads: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
