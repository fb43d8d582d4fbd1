"""Map a cell field of a run on a horizontal layer of cells.

usage: /usr/bin/python3 postproc/plot_field.py DIR/PREFIX [--field pressure] [--time T | --step N]
                                               [--z Z] [--component K] [--scale S --unit U] [-o OUT.png]
Draws the cells whose centres are nearest to z = Z (default: the lowest
layer) as seen from above, coloured by the field at output step N (default:
the last) or at the output time nearest to T: a cell field (pressure,
pressure_change, region, a stress component with --component 0..5 in the
order XX YY ZZ XY YZ XZ). --scale divides the values (e.g. 1e6 with --unit
MPa)."""
import argparse
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from geoblock_h5 import Run, script_main  # noqa: E402


def footprint(points):
    """The four lowest corners of a hexahedron, in order around their centre (x, y)."""
    low = points[np.argsort(points[:, 2], kind="stable")[:4], :2]
    c = low.mean(axis=0)
    return low[np.argsort(np.arctan2(low[:, 1] - c[1], low[:, 0] - c[0]))]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run", help="output directory/prefix of a run")
    ap.add_argument("--field", default="pressure", help="a cell field (default pressure)")
    ap.add_argument("--component", type=int, default=0, help="component of a vector or tensor field")
    ap.add_argument("--step", type=int, default=-1, help="output step (default: the last)")
    ap.add_argument("--time", type=float, help="the output time nearest to this one instead of --step")
    ap.add_argument("--z", type=float, help="the layer of cells whose centres are nearest to this z")
    ap.add_argument("--scale", type=float, default=1.0, help="divide the values by this")
    ap.add_argument("--unit", default="", help="unit of the scaled values, for the colour bar")
    ap.add_argument("-o", "--output", default="", help="figure file (default DIR/PREFIX_FIELD.png)")
    a = ap.parse_args()
    run = Run(os.path.dirname(a.run) or ".", os.path.basename(a.run))
    times = run.times()
    step = a.step if a.time is None else int(np.argmin(np.abs(times - a.time)))
    values = run.field(a.field, step)
    if values.ndim > 1:
        values = values[:, a.component]
    values = values / a.scale
    zc = run.cell_centres()[:, 2]
    z = zc.min() if a.z is None else a.z
    layer = np.isclose(zc, zc[np.argmin(np.abs(zc - z))], rtol=0, atol=1e-9 * max(np.ptp(zc), 1.0))
    polys = np.array([footprint(run.coords[cell]) for cell in run.conn[layer]])
    fig, ax = plt.subplots(figsize=(5.6, 4.6))
    coll = PolyCollection(polys, cmap="viridis", edgecolors="0.5", linewidths=0.2)
    coll.set_array(values[layer])
    ax.add_collection(coll)
    ax.autoscale_view()
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    label = a.field + (f"[{a.component}]" if run.field(a.field, step).ndim > 1 else "")
    fig.colorbar(coll, ax=ax, label=label + (f" [{a.unit}]" if a.unit else ""))
    ax.set_title(f"{run.prefix}: {label} at t = {times[step]:.4g}")
    fig.tight_layout()
    out = a.output or os.path.join(run.dir, f"{run.prefix}_{a.field}.png")
    fig.savefig(out, dpi=100)
    print(f"figure: {out}")
    return 0


if __name__ == "__main__":
    script_main(main)
