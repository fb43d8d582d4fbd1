"""Check a 'poromechanics_faults' run of a Terzaghi column cut by a
horizontal fracture held at zero pressure (tests/decks/poro_faults_test.nml).

usage: check_poro_faults.py DIR PREFIX --cut ZF [--times T1,T2,...] [--tol TOL]
           [--flux-tol FTOL] [--top drained|impermeable]

The column 0 <= z <= H (H = 10 m; material of tests/decks/terzaghi_test.nml:
E = 1e8 Pa, nu = 0.25, b = 1, M = 1e10 Pa, k = 1e-12 m^2, mu = 1e-3 Pa s),
base impermeable and fixed, top loaded by sigma0 = 1 MPa and impermeable
(--top impermeable, the default), cut at z = ZF by the fracture. Each part
is then a single-drained Terzaghi column of its own height, drained at the
fracture: the lower one of height L1 = ZF (impermeable base), the upper one
of height L2 = H - ZF (impermeable top). At each requested time t (the
nearest output step) the check asks:
  - every cell's pressure within TOL * p0 of the exact cell average of its
    part's Terzaghi solution;
  - the fracture's inflow from both sides (the output's 'leakoff' summed over
    the fracture, m^3/s) within FTOL of the analytical leak-off
        A (k / mu) 2 p0 (S(T1) / L1 + S(T2) / L2),  S(T) = sum_m exp(-lam_m^2 T),
    the derivative of the Terzaghi series at the drained face
    (lam_m = (2m + 1) pi / 2, T_i = c_v t / L_i^2, A = 1 m^2).
Prints one line per check and exits 1 on a failure."""
import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "postproc"))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "common"))
import h5py  # noqa: E402
import numpy as np  # noqa: E402
from analytical import PoroParams, Terzaghi  # noqa: E402
from geoblock_h5 import Run  # noqa: E402
from vreport import record  # noqa: E402

H, SIGMA0, AREA = 10.0, 1.0e6, 1.0
PAR = PoroParams(E=1e8, nu=0.25, b=1.0, M=1e10, k=1e-12, mu=1e-3)


def cell_average(tz, zeta_c, h, t):
    """Mean of the part's Terzaghi pressure over a cell of height h whose
    centre lies at distance zeta_c from the part's impermeable end."""
    g, w = np.polynomial.legendre.leggauss(8)
    return sum(wi * tz.pressure(np.clip(zeta_c + 0.5 * h * gi, 0.0, tz.H), t) for gi, wi in zip(g, w)) / 2.0


def series_flux(tz, t):
    """Outflow per area at the drained face, (k/mu) |dp/dz| [m/s]."""
    lam = (2 * np.arange(4000) + 1) * np.pi / 2
    T = tz.time_factor(t)
    return (PAR.k / PAR.mu) * 2.0 * tz.p0 * np.sum(np.exp(-lam ** 2 * T)) / tz.H


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dir")
    ap.add_argument("prefix")
    ap.add_argument("--cut", type=float, required=True)
    ap.add_argument("--times", default="2,10,40")
    ap.add_argument("--tol", type=float, default=0.01)
    ap.add_argument("--flux-tol", type=float, default=0.01)
    a = ap.parse_args()
    run = Run(a.dir, a.prefix)
    zc = run.cell_centres()[:, 2]
    h = H / len(np.unique(np.round(zc, 9)))
    lower, upper = Terzaghi(PAR, a.cut, SIGMA0), Terzaghi(PAR, H - a.cut, SIGMA0)
    below = zc < a.cut
    zeta = np.where(below, zc, H - zc)      # distance from the part's impermeable end
    times = run.times()
    ok = True
    label = f"Terzaghi column cut at z = {a.cut:.4g} m by a drained fracture, {len(np.unique(np.round(zc, 9)))} cells"
    for target in [float(x) for x in a.times.split(",")]:
        i = int(np.argmin(np.abs(times - target)))
        t = times[i]
        ex = np.where(below, cell_average(lower, zeta, h, t), cell_average(upper, zeta, h, t))
        p = run.field("pressure", i)
        err = np.max(np.abs(p - ex)) / lower.p0
        good = err <= a.tol and i > 0
        record(label + f", t = {t:.3g} s", "pressure (largest cell error / p0)", err, a.tol, passed=good)
        print(f"t = {t:.3f} s (T lower {lower.time_factor(t):.4f}, upper {upper.time_factor(t):.4f}): "
              f"largest cell pressure error {err:.3e} p0 (tol {a.tol:g}) {'ok' if good else 'FAIL'}")
        ok = ok and good
        with h5py.File(run.steps[i], "r") as f:
            leak = float(np.sum(f["fractures/leakoff"]))
        exact = AREA * (series_flux(lower, t) + series_flux(upper, t))
        ferr = abs(leak - exact) / exact
        good = ferr <= a.flux_tol and i > 0
        record(label + f", t = {t:.3g} s", "leak-off into the fracture (relative error)", ferr, a.flux_tol,
               passed=good)
        print(f"t = {t:.3f} s: leak-off {leak:.6e} m3/s, analytical {exact:.6e} m3/s, relative error {ferr:.3e} "
              f"(tol {a.flux_tol:g}) {'ok' if good else 'FAIL'}")
        ok = ok and good
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
