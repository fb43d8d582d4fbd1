"""Physical checks of the reduced Treporti and Reservoir stand-ins
(tests/decks/treporti_small.nml, reservoir_small.nml).

usage: check_standins.py treporti|reservoir DIR [--balance-tol TOL]
Prints one line per check ('FAIL' in the failing ones); exit 1 on failure.

treporti: the settlement under the load's centre is positive (downwards),
  grows from step to step (0.1 and 10 days), and is at
  least ten times that at the far corner; at 10 days, on the load's axis,
  the excess pressure in the sand layer sand2 is below that in the clay
  layers above and below it (clay1, clay2): the sands drain first.
reservoir: after 1 and 100 days the pressure in both producers' columns
  is below that far away in the reservoir, in both injectors' above it, and
  after 1 day the change far away is under a tenth of every well's; and the fluid balance of the closed block: with b = 1 the mass
  balance summed over the cells is
      integral of u_z over the top + sum_c V_c p_c / M_c = sum_i rate_i V_i t
  (the stabilization's face terms cancel in the sum, every face is
  impermeable, the sides and bottom have u.n = 0, and on these
  axis-aligned cells the bilinear u_z integrates exactly as the mean of the
  face's corners times its area), within TOL of the volume the wells put
  in."""
import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "postproc"))
import numpy as np  # noqa: E402
from geoblock_h5 import Run  # noqa: E402


def probes(d, prefix):
    rows = np.genfromtxt(os.path.join(d, prefix + "_probes.csv"), delimiter=",", names=True)
    return rows


def check(ok, text):
    print(("" if ok else "FAIL ") + text)
    return ok


def treporti(d):
    p = probes(d, "treporti")
    cols = p.dtype.names
    centre, far = -p[cols[2]], -p[cols[4]]
    ok = check(np.all(centre > 0) and np.all(np.diff(centre) > 0),
               f"settlement under the load {', '.join(f'{s:.4f}' for s in centre)} m: positive, growing")
    ok &= check(np.all(centre > 10 * np.abs(far)),
                f"far corner {', '.join(f'{s:.2e}' for s in far)} m: under a tenth of it")
    clay1, sand2, clay2 = p[cols[5]][-1], p[cols[6]][-1], p[cols[7]][-1]
    ok &= check(sand2 < clay1 and sand2 < clay2 and sand2 >= 0,
                f"at 10 days on the axis: clay1 {clay1:.0f} Pa, sand2 {sand2:.0f} Pa, clay2 {clay2:.0f} Pa (sand lowest)")
    return ok


def reservoir(d, tol):
    run = Run(d, "reservoir")
    par = run.parameters()
    m_of = {g["region"]: g["biot_modulus"] for g in par["material"]}
    assert all(g["biot"] == 1.0 for g in par["material"]), "the balance below assumes b = 1"
    rate_of = {g["region"]: g["rate"] for g in par["source"]}
    xdmf = open(os.path.join(d, "reservoir.xdmf")).read()
    legend = xdmf.split('Name="region" Value="cell field, region id: ')[1].split('"')[0]
    names = {int(k): v for k, v in (s.split(" = ") for s in legend.split(", "))}
    x = run.coords[run.conn]                                  # (cells, 8, 3)
    vol = np.prod(x.max(axis=1) - x.min(axis=1), axis=1)      # axis-aligned boxes
    ok = True
    p_rows = probes(d, "reservoir")
    cols = p_rows.dtype.names
    for s, t in enumerate(run.times()):
        reg = run.field("region", s)
        inv_m = np.array([1.0 / m_of[names[r]] for r in reg])
        rate = np.array([rate_of.get(names[r], 0.0) for r in reg])
        u = run.field("displacement", s)
        p = run.field("pressure", s)
        top = 0.0
        for c in range(run.conn.shape[0]):
            nodes = run.conn[c, 4:]                          # the upper face of a box cell
            if np.allclose(run.coords[nodes, 2], 0.0):
                top += u[nodes, 2].mean() * vol[c] / (x[c, :, 2].max() - x[c, :, 2].min())
        stored = top + np.sum(vol * p * inv_m)
        put_in = np.sum(rate * vol) * t
        err = abs(stored - put_in) / np.sum(np.abs(rate * vol) * t)
        ok &= check(err <= tol, f"t = {t:.4g} s: stored {stored:.6e} m^3 (ground {top:.4e}, fluid {stored - top:.4e}), "
                                f"wells {put_in:.6e} m^3: error {err:.1e} of the wells' volume (tol {tol:.0e})")
        pw = [p_rows[cols[2 + k]][s] for k in range(5)]
        far = pw[4]
        wells_ok = pw[0] < far and pw[1] < far and pw[2] > far and pw[3] > far
        if s == 0:
            wells_ok = wells_ok and 10 * abs(far) < min(abs(v) for v in pw[:4])
        ok &= check(wells_ok,
                    f"t = {t:.4g} s: producers {pw[0]:.3e}, {pw[1]:.3e} Pa, injectors {pw[2]:.3e}, {pw[3]:.3e} Pa, "
                    f"far {pw[4]:.2e} Pa")
    return ok


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("case", choices=["treporti", "reservoir"])
    ap.add_argument("dir")
    ap.add_argument("--balance-tol", type=float, default=1e-9)
    a = ap.parse_args()
    ok = treporti(a.dir) if a.case == "treporti" else reservoir(a.dir, a.balance_tol)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
