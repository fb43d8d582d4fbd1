"""Compare a geoblock Mandel run (input/mandel.nml material, quarter model
0 < x < a, 0 < y < b) with the analytical solution.

usage: check_mandel.py DIR PREFIX [--tol TOL] [--times T1,T2,...]
At each requested dimensionless time T = c t / a^2 (nearest output step) the
cell pressures averaged over the cells at x ~ 0, a/2 and 0.9 a (all y) are
compared with the analytical pressure at those x: |p_h - p| / p0 <= TOL.
Also checks that the simulated centre pressure rises above p0 at early
times (the Mandel-Cryer effect) and that the undrained step gives p0."""
import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "postproc"))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "common"))
import numpy as np  # noqa: E402
from analytical import Mandel, PoroParams  # noqa: E402
from vreport import record  # noqa: E402
from geoblock_h5 import Run  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dir")
    ap.add_argument("prefix")
    ap.add_argument("--tol", type=float, default=0.02)
    ap.add_argument("--times", default="0.01,0.05,0.1,0.3,0.6")
    a_ = ap.parse_args()
    m = Mandel.from_traction(PoroParams(E=1e9, nu=0.25, b=1.0, M=1e10, k=1e-14, mu=1e-3), 1.0, 1.0, 1e6)
    run = Run(a_.dir, a_.prefix)
    xc = run.cell_centres()[:, 0]
    xs = np.unique(np.round(xc, 9))
    times = run.times()
    T = m.c * times
    ok = True

    def column(x):  # cells nearest to x
        xn = xs[np.argmin(np.abs(xs - x))]
        return np.isclose(xc, xn), xn

    p = run.field("pressure", 0)
    e0 = np.max(np.abs(p - m.p0)) / m.p0
    good = e0 < 1e-6
    record("Mandel, undrained step", "pressure p0 (largest relative error)", e0, 1e-6)
    print(f"undrained step: max |p - p0| / p0 = {e0:.2e} (tol 1e-6) {'ok' if good else 'FAIL'}")
    ok = ok and good
    for target in [float(v) for v in a_.times.split(",")]:
        i = int(np.argmin(np.abs(T - target)))
        p = run.field("pressure", i)
        errs = []
        for x in (0.0, 0.5, 0.9):
            sel, xn = column(x)
            errs.append(abs(p[sel].mean() - float(m.pressure(xn, times[i]))) / m.p0)
        good = max(errs) <= a_.tol
        record(f"Mandel, T = {T[i]:.4f}", "pressure at x = 0, a/2, 0.9a (largest |p_h - p| / p0)", max(errs),
               a_.tol, passed=good)
        ok = ok and good
        print(f"T = {T[i]:.4f}: |p_h - p| / p0 at x = 0, a/2, 0.9a: " +
              ", ".join(f"{e:.2e}" for e in errs) + f" (tol {a_.tol:g}) {'ok' if good else 'FAIL'}")
    sel, xn = column(0.0)
    centre = np.array([run.field("pressure", i)[sel].mean() for i in range(len(times))])
    peak = centre.max() / m.p0
    exact_peak = max(float(m.pressure(xn, t)) for t in times) / m.p0
    good = peak > 1.01
    record("Mandel, centre", "Mandel-Cryer peak p / p0 (error against the analytical peak)",
           abs(peak - exact_peak), "peak > 1.01", passed=good)
    ok = ok and good
    print(f"Mandel-Cryer effect: centre pressure peaks at {peak:.4f} p0 (analytical {exact_peak:.4f} p0) "
          f"{'ok' if good else 'FAIL'}")
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
