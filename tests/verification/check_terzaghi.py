"""Compare a geoblock Terzaghi run with the analytical series.

usage: check_terzaghi.py DIR PREFIX M [--times T1,T2,...] [--tol TOL] [--print]
Material and geometry: those of tests/decks/terzaghi_test.nml (E = 1e8 Pa,
nu = 0.25, b = 1, M as given (inf: incompressible), k = 1e-12 m^2,
mu = 1e-3 Pa s, H = 10 m, sigma0 = 1 MPa).
Checks: the undrained pressure equals p0 (1e-10 relative) and the settlement
of the undrained step equals sigma0 H / K_vu; at each requested dimensionless
time T the relative L2 error of the cell pressures against the exact cell
averages is at most TOL. Prints one line per check; exits 1 on a failure.
With --print it prints the errors at every step (for convergence studies)."""
import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "postproc"))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "common"))
import numpy as np  # noqa: E402
from analytical import PoroParams, Terzaghi  # noqa: E402
from geoblock_h5 import Run  # noqa: E402
from vreport import record  # noqa: E402

H, SIGMA0 = 10.0, 1.0e6


def cell_average(tz, zc, h, t):
    g, w = np.polynomial.legendre.leggauss(8)
    return sum(wi * tz.pressure(zc + 0.5 * h * gi, t) for gi, wi in zip(g, w)) / 2.0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dir")
    ap.add_argument("prefix")
    ap.add_argument("M", type=float)
    ap.add_argument("--times", default="0.02,0.08,0.15")
    ap.add_argument("--tol", type=float, default=0.01)
    ap.add_argument("--print", action="store_true")
    a = ap.parse_args()
    par = PoroParams(E=1e8, nu=0.25, b=1.0, M=a.M, k=1e-12, mu=1e-3)
    tz = Terzaghi(par, H, SIGMA0)
    run = Run(a.dir, a.prefix)
    zc = run.cell_centres()[:, 2]
    h = H / len(np.unique(np.round(zc, 9)))
    times = run.times()
    ok = True
    p = run.field("pressure", 0)
    e0 = np.max(np.abs(p - tz.p0)) / tz.p0
    s0 = -run.field("displacement", 0)[:, 2].min()
    s0_exact = SIGMA0 * H / par.K_vu
    good = e0 < 1e-10 and abs(s0 - s0_exact) / s0_exact < 1e-10
    record(f"Terzaghi column, {len(np.unique(np.round(zc, 9)))} cells, undrained step", "pressure p0 (largest error)",
           e0, 1e-10)
    record(f"Terzaghi column, {len(np.unique(np.round(zc, 9)))} cells, undrained step", "settlement (relative error)",
           abs(s0 - s0_exact) / s0_exact, 1e-10)
    print(f"undrained step: p0 error {e0:.2e}, settlement {s0:.6e} vs {s0_exact:.6e} {'ok' if good else 'FAIL'}")
    ok = ok and good
    T = np.array([tz.time_factor(t) for t in times])
    if a.print:
        for i in range(1, len(times)):
            ex = cell_average(tz, zc, h, times[i])
            err = np.sqrt(np.sum((run.field("pressure", i) - ex) ** 2) / np.sum(ex ** 2))
            print(f"t {times[i]:10.4f} T {T[i]:.4f} relative L2 error {err:.3e}")
    for target in [float(x) for x in a.times.split(",")]:
        i = int(np.argmin(np.abs(T - target)))
        ex = cell_average(tz, zc, h, times[i])
        err = np.sqrt(np.sum((run.field("pressure", i) - ex) ** 2) / np.sum(ex ** 2))
        good = err <= a.tol and i > 0
        record(f"Terzaghi column, {len(np.unique(np.round(zc, 9)))} cells, T = {T[i]:.4f}",
               "pressure (relative L2 error)", err, a.tol, passed=good)
        print(f"T = {T[i]:.4f} (t = {times[i]:.2f} s): pressure relative L2 error {err:.3e} "
              f"(tol {a.tol:g}) {'ok' if good else 'FAIL'}")
        ok = ok and good
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
