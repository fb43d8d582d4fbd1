"""Plot a geoblock Mandel run against the analytical solution.

usage: /usr/bin/python3 postproc/plot_mandel.py [DIR] [PREFIX] [OUT.png]
(defaults: out mandel out/mandel_pressure.png). Material, geometry and load
of input/mandel.nml. Left: pressure against time at x = 0, a/2, 0.9a
(markers: geoblock, cell averages over y; lines: analytical). Right: pressure
profiles along x at a few times."""
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(__file__))
from analytical import Mandel, PoroParams  # noqa: E402
from geoblock_h5 import Run  # noqa: E402


def main():
    d = sys.argv[1] if len(sys.argv) > 1 else "out"
    prefix = sys.argv[2] if len(sys.argv) > 2 else "mandel"
    png = sys.argv[3] if len(sys.argv) > 3 else os.path.join(d, prefix + "_pressure.png")
    m = Mandel.from_traction(PoroParams(E=1e9, nu=0.25, b=1.0, M=1e10, k=1e-14, mu=1e-3), 1.0, 1.0, 1e6)
    run = Run(d, prefix)
    t = run.times()
    xc = run.cell_centres()[:, 0]
    xs = np.unique(np.round(xc, 9))
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    tt = np.geomspace(max(t[1], 1e-3), t[-1], 300)
    for x, col in zip((0.0, 0.5, 0.9), ("C0", "C1", "C2")):
        xn = xs[np.argmin(np.abs(xs - x))]
        sel = np.isclose(xc, xn)
        ps = [run.field("pressure", i)[sel].mean() / m.p0 for i in range(1, len(t))]
        ax1.semilogx(t[1:], ps, "o", ms=3, color=col, label=f"geoblock x = {xn:.3f} m")
        ax1.semilogx(tt, m.pressure(xn, tt) / m.p0, "-", color=col, label=f"analytical x = {xn:.3f} m")
    ax1.set_xlabel("time [s]")
    ax1.set_ylabel("p / p0")
    ax1.set_title("Mandel: pressure against time")
    ax1.legend(fontsize=7)
    for T in (0.01, 0.1, 0.3, 1.0):
        i = int(np.argmin(np.abs(m.c * t - T)))
        p = run.field("pressure", i)
        prof = [p[np.isclose(xc, x)].mean() / m.p0 for x in xs]
        ax2.plot(xs, prof, "o", ms=3)
        xx = np.linspace(0, 1, 200)
        ax2.plot(xx, m.pressure(xx, t[i]) / m.p0, "-", color=ax2.lines[-1].get_color(), label=f"T = {m.c * t[i]:.3f}")
    ax2.set_xlabel("x [m]")
    ax2.set_ylabel("p / p0")
    ax2.set_title("profiles (markers: geoblock, lines: analytical)")
    ax2.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    print(png)


if __name__ == "__main__":
    main()
