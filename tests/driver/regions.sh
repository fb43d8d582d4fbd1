#!/usr/bin/env bash
# Box regions (&region): a 2 x 2 x 6 column in layers carved by three
# groups, one of them an overlapping lens that later wins, on 1 and 2 ranks:
# the cells per region in the log line and in the HDF5 'region' field, the
# XDMF legend of the region ids; then the same column without the lens as
# an oedometer (rollers, a top load): the settlement of each layer is
# sigma h / (lambda + 2 mu) of its own region's material, exact for Q1 up
# to the solver tolerance, so a cell put in the wrong region shows.
set -u
cd "$(dirname "$0")/../.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
PY=${PYTHON:-/usr/bin/python3}
out=build/test-out/regions
rm -rf "$out"; mkdir -p "$out"
pass=0; fail=0
ok() { echo "  ok    $1"; pass=$((pass + 1)); }
ko() { echo "  FAIL  $1"; fail=$((fail + 1)); }

deck() {   # deck NAME LENS(yes|no)
  local lens=""
  [ "$2" = yes ] && lens="&region
  name = 'lens', lower = 0, 0, 1, upper = 1, 1, 3
/
&material
  region = 'lens', young = 1.0e9, poisson = 0.25
/"
  cat > "$out/$1.nml" <<DECK
&mesh
  source = 'box', nx = 2, ny = 2, nz = 6, lower = 0, 0, 0, upper = 2, 2, 6
/
&region
  name = 'sand', upper(3) = 2
/
&region
  name = 'clay', lower(3) = 2, upper(3) = 4
/
$lens
&material
  region = 'domain', young = 4.0e9, poisson = 0.25
/
&material
  region = 'sand', young = 2.0e9, poisson = 0.3
/
&material
  region = 'clay', young = 5.0e8, poisson = 0.2
/
$(for bc in "zmin ux = 0, uy = 0, uz = 0" "xmin ux = 0" "xmax ux = 0" "ymin uy = 0" "ymax uy = 0"; do
  printf "&boundary\n  set = '%s', type = 'displacement', %s\n/\n" "${bc%% *}" "${bc#* }"; done)
&boundary
  set = 'zmax', type = 'traction', traction = 0, 0, -1.0e6
/
&solver
  method = 'cg', precon = 'boomeramg', rtol = 1.0e-12
/
&output
  dir = '$out/$1', prefix = 'col'
/
DECK
}
deck lens yes
deck layers no
for np in 1 2; do
  for case in lens layers; do
    if ! timeout 120 mpirun --oversubscribe -np "$np" bin/geoblock "$out/$case.nml" > "$out/${case}_np$np.stdout" 2>&1 < /dev/null; then
      ko "$case deck on $np rank(s) fails, see $out/${case}_np$np.stdout"; continue
    fi
    if [ "$case" = lens ]; then
      want="regions: 'domain' 8 cells, 'sand' 7 cells, 'clay' 7 cells, 'lens' 2 cells"
      if grep -qF "$want" "$out/$case/col.log"; then ok "$np rank(s): log line \"$want\""
      else ko "$np rank(s): log lacks \"$want\": $(grep -m1 '^regions' "$out/$case/col.log")"; fi
    fi
    if r=$($PY - "$out/$case" "$case" <<'PY' 2>&1
import sys, re
import numpy as np, h5py
d, case = sys.argv[1], sys.argv[2]
with h5py.File(f"{d}/col_mesh.h5") as m:
    xyz = m["coords"][()]
    conn = m["connectivity"][()]
with h5py.File(f"{d}/col_0000.h5") as f:
    reg = f["region"][()]
    u = f["displacement"][()]
legend = re.search(r'Name="region" Value="cell field, region id: ([^"]*)"', open(f"{d}/col.xdmf").read()).group(1)
names = {int(k): v for k, v in (p.split(" = ") for p in legend.split(", "))}
c = xyz[conn].mean(axis=1)                       # cell centres
count = {names[i]: int((reg == i).sum()) for i in names}
if case == "lens":
    assert count == {"domain": 8, "sand": 7, "clay": 7, "lens": 2}, count
    lens = (c[:, 0] < 1) & (c[:, 1] < 1) & (c[:, 2] > 1) & (c[:, 2] < 3)
    assert all(names[i] == "lens" for i in reg[lens]), "lens cells"
    print(f"HDF5 region counts {count}, legend {legend}")
else:
    assert count == {"domain": 8, "sand": 8, "clay": 8}, count
    want = {"sand": c[:, 2] < 2, "clay": (c[:, 2] > 2) & (c[:, 2] < 4), "domain": c[:, 2] > 4}
    for i, n in names.items():
        assert np.array_equal(reg == i, want[n]), n
    # oedometer: settlement at the top = sum over layers of sigma h / M
    def m_mod(e, nu):
        return e * (1 - nu) / ((1 + nu) * (1 - 2 * nu))
    sig, h = 1.0e6, 2.0
    exact = sig * h * (1 / m_mod(2e9, 0.3) + 1 / m_mod(5e8, 0.2) + 1 / m_mod(4e9, 0.25))
    top = np.isclose(xyz[:, 2], 6.0)
    uz = -u[top, 2]
    err = abs(uz - exact).max() / exact
    assert err < 1e-9, (uz, exact, err)      # exact for Q1; the CG tolerance 1e-12 bounds the rest
    print(f"cells per region {count}; oedometer settlement {uz.mean():.6e} m, exact {exact:.6e}, rel. error {err:.1e}")
PY
); then ok "$np rank(s), $case: $r"; else ko "$np rank(s), $case: $r"; fi
  done
done
echo "suite regions: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
