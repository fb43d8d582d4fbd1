"""Plot a geoblock Terzaghi run against the analytical solution.

usage: /usr/bin/python3 postproc/plot_terzaghi.py [DIR] [PREFIX] [OUT.png]
(defaults: out terzaghi DIR/PREFIX_pressure.png). The material (first
&material), the column height H (&mesh upper(3) - lower(3)) and the load
(the z component of the traction &boundary on zmax) are read from the run's
DIR/PREFIX_parameters.nml. Pressure profiles along the column at a few
dimensionless times T = c_v t / H^2 (markers: geoblock, lines: analytical)."""
import argparse
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(__file__))
from analytical import PoroParams, Terzaghi  # noqa: E402
from geoblock_h5 import Run, script_main  # noqa: E402


def top_load(par):
    """Magnitude [Pa] of the compressive traction of the &boundary on zmax."""
    for bc in par.get("boundary", []):
        if bc.get("set") == "zmax" and bc.get("type") == "traction":
            return -float(bc["traction"][2])
    raise ValueError("the run has no traction condition on zmax")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dir", nargs="?", default="out", help="output directory of the run (default out)")
    ap.add_argument("prefix", nargs="?", default="terzaghi", help="output prefix of the run (default terzaghi)")
    ap.add_argument("png", nargs="?", help="figure file (default DIR/PREFIX_pressure.png)")
    args = ap.parse_args()
    d, prefix = args.dir, args.prefix
    png = args.png or os.path.join(d, prefix + "_pressure.png")
    run = Run(d, prefix)
    par = run.parameters()
    mesh = par["mesh"][0]
    z0, H = float(mesh["lower"][2]), float(mesh["upper"][2]) - float(mesh["lower"][2])
    tz = Terzaghi(PoroParams.from_namelist(par["material"][0]), H, top_load(par))
    t = run.times()
    zc = run.cell_centres()[:, 2] - z0
    fig, ax = plt.subplots(figsize=(5.5, 5))
    z = np.linspace(0, H, 300)
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
    script_main(main)
