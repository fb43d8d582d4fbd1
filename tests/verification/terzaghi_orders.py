"""Observed convergence orders of Terzaghi runs under mesh refinement.

usage: terzaghi_orders.py T_CHECK MIN_P_ORDER MIN_U_ORDER DIR1 DIR2 DIR3 ...
(runs with prefix 'terzaghi', nz doubling, the same small time steps). At
the output time nearest T_CHECK [s] it computes the relative L2 errors of the
cell pressures (against exact cell averages) and of the nodal vertical
displacements (against the exact u_z), prints them with the observed orders
and exits 1 if an order falls below its minimum."""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "postproc"))
import numpy as np  # noqa: E402
from analytical import PoroParams, Terzaghi  # noqa: E402
from geoblock_h5 import Run  # noqa: E402

from check_terzaghi import H, SIGMA0, cell_average  # noqa: E402


def errors(d, t_check, tz):
    run = Run(d, "terzaghi")
    times = run.times()
    i = int(np.argmin(np.abs(times - t_check)))
    t = times[i]
    zc = run.cell_centres()[:, 2]
    h = H / len(np.unique(np.round(zc, 9)))
    ex = cell_average(tz, zc, h, t)
    ep = np.sqrt(np.sum((run.field("pressure", i) - ex) ** 2) / np.sum(ex ** 2))
    z = run.coords[:, 2]
    uz = run.field("displacement", i)[:, 2]
    ue = tz.displacement(z, t)
    eu = np.sqrt(np.sum((uz - ue) ** 2) / np.sum(ue ** 2))
    return h, t, ep, eu


def main():
    t_check, min_p, min_u = float(sys.argv[1]), float(sys.argv[2]), float(sys.argv[3])
    tz = Terzaghi(PoroParams(E=1e8, nu=0.25, b=1.0, M=1e10, k=1e-12, mu=1e-3), H, SIGMA0)
    rows = [errors(d, t_check, tz) for d in sys.argv[4:]]
    ok = True
    for k, (h, t, ep, eu) in enumerate(rows):
        line = f"h {h:.4f} t {t:.2f}: pressure L2 error {ep:.3e}, displacement L2 error {eu:.3e}"
        if k > 0:
            op = np.log(rows[k - 1][2] / ep) / np.log(rows[k - 1][0] / h)
            ou = np.log(rows[k - 1][3] / eu) / np.log(rows[k - 1][0] / h)
            line += f"; observed orders pressure {op:.2f}, displacement {ou:.2f}"
            good = op >= min_p and ou >= min_u
            ok = ok and good
            line += " ok" if good else f" FAIL (need {min_p}, {min_u})"
        print(line)
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
