"""Plot a geoblock Terzaghi run against the analytical solution.

usage: /usr/bin/python3 postproc/plot_terzaghi.py [DIR] [PREFIX] [OUT.png] [M]
(defaults: out terzaghi out/terzaghi_pressure.png 1e10). Material and
geometry of input/terzaghi.nml. Pressure profiles along the column at a few
dimensionless times T = c_v t / H^2 (markers: geoblock, lines: analytical)."""
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(__file__))
from analytical import PoroParams, Terzaghi  # noqa: E402
from geoblock_h5 import Run  # noqa: E402


def main():
    d = sys.argv[1] if len(sys.argv) > 1 else "out"
    prefix = sys.argv[2] if len(sys.argv) > 2 else "terzaghi"
    png = sys.argv[3] if len(sys.argv) > 3 else os.path.join(d, prefix + "_pressure.png")
    M = float(sys.argv[4]) if len(sys.argv) > 4 else 1e10
    tz = Terzaghi(PoroParams(E=1e8, nu=0.25, b=1.0, M=M, k=1e-12, mu=1e-3), 10.0, 1e6)
    run = Run(d, prefix)
    t = run.times()
    zc = run.cell_centres()[:, 2]
    fig, ax = plt.subplots(figsize=(5.5, 5))
    z = np.linspace(0, 10, 300)
    for T in (0.01, 0.05, 0.2, 0.5, 1.0):
        i = int(np.argmin(np.abs(tz.time_factor(t) - T)))
        line, = ax.plot(tz.pressure(z, t[i]) / tz.p0, z, "-", label=f"T = {tz.time_factor(t[i]):.3f}")
        ax.plot(run.field("pressure", i) / tz.p0, zc, "o", ms=3, color=line.get_color())
    ax.set_xlabel("p / p0")
    ax.set_ylabel("z [m]")
    ax.set_title("Terzaghi (markers: geoblock, lines: analytical)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    print(png)


if __name__ == "__main__":
    main()
