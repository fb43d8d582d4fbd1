"""Plot a geoblock Mandel run against the analytical solution.

usage: /usr/bin/python3 postproc/plot_mandel.py [DIR] [PREFIX] [OUT.png]
(defaults: out mandel DIR/PREFIX_pressure.png). The material (first
&material), the quarter's size a x b (&mesh upper - lower) and the plate
stress are read from the run's DIR/PREFIX_parameters.nml; the stress from
the header of the plate's history file (written by make_mandel_history.py),
else --sigma. Left: pressure against time at x = 0, a/2, 0.9a (markers:
geoblock, cell averages over y; lines: analytical). Right: pressure
profiles along x at a few times."""
import argparse
import os
import re
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(__file__))
from analytical import Mandel, PoroParams  # noqa: E402
from geoblock_h5 import Run, script_main  # noqa: E402


def plate_stress(par, default):
    """The plate stress [Pa] named in the header of the history file of the
    &boundary on ymax ('sigma=...'), else default."""
    for bc in par.get("boundary", []):
        hist = bc.get("history", "")
        if bc.get("set") == "ymax" and hist:
            with open(hist) as f:
                m = re.search(r"sigma=([-+0-9.eE]+)", f.read(4096))
            if m:
                return float(m.group(1))
    if default is None:
        raise ValueError("no plate stress: the ymax history file names none; give --sigma")
    return default


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dir", nargs="?", default="out", help="output directory of the run (default out)")
    ap.add_argument("prefix", nargs="?", default="mandel", help="output prefix of the run (default mandel)")
    ap.add_argument("png", nargs="?", help="figure file (default DIR/PREFIX_pressure.png)")
    ap.add_argument("--sigma", type=float, help="plate stress [Pa] when the history file names none")
    args = ap.parse_args()
    d, prefix = args.dir, args.prefix
    png = args.png or os.path.join(d, prefix + "_pressure.png")
    run = Run(d, prefix)
    par = run.parameters()
    mesh = par["mesh"][0]
    a = float(mesh["upper"][0]) - float(mesh["lower"][0])
    b = float(mesh["upper"][1]) - float(mesh["lower"][1])
    m = Mandel.from_traction(PoroParams.from_namelist(par["material"][0]), a, b, plate_stress(par, args.sigma))
    t = run.times()
    xc = run.cell_centres()[:, 0]
    xs = np.unique(np.round(xc, 9))
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    tt = np.geomspace(max(t[1], 1e-3), t[-1], 300)
    for x, col in zip((0.0, 0.5 * a, 0.9 * a), ("C0", "C1", "C2")):
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
        xx = np.linspace(0, a, 200)
        ax2.plot(xx, m.pressure(xx, t[i]) / m.p0, "-", color=ax2.lines[-1].get_color(), label=f"T = {m.c * t[i]:.3f}")
    ax2.set_xlabel("x [m]")
    ax2.set_ylabel("p / p0")
    ax2.set_title("profiles (markers: geoblock, lines: analytical)")
    ax2.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    print(png)


if __name__ == "__main__":
    script_main(main)
