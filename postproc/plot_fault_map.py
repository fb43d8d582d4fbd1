"""Map one fault of a contact run: its elements unrolled into the fault's
plane (along strike against depth), coloured by slip, CFF and status.

usage: /usr/bin/python3 postproc/plot_fault_map.py DIR/PREFIX [--fault NAME] [--step N] [-o OUT.png]
Reads the fault fields of output step N (default: the last) from
DIR/PREFIX_mesh.h5 and DIR/PREFIX_NNNN.h5: the elements' corners are
placed by their coordinate along the fault's strike (the horizontal
direction in its mean plane) and their z. Three panels: slip magnitude [m], Coulomb failure function
CFF [MPa] (0 where slipping, negative in stick) and status (stick, slip,
open). Prints the fault's stick/slip/open counts and largest slip."""
import argparse
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402
from matplotlib.colors import ListedColormap  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from geoblock_h5 import Run, script_main  # noqa: E402
from plot_faults import STATUS_COLOURS, STATUS_NAMES, fault_names  # noqa: E402


def plane_axes(normal):
    """Unit vectors along strike (horizontal in the plane) and the plane's normal."""
    n = normal / np.linalg.norm(normal)
    s = np.cross(n, [0.0, 0.0, 1.0])
    if np.linalg.norm(s) < 1e-9:           # a horizontal fault: strike along x
        s = np.array([1.0, 0.0, 0.0])
    return s / np.linalg.norm(s), n


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run", help="output directory/prefix of a contact run")
    ap.add_argument("--fault", default="", help="the fault to draw (default: the first)")
    ap.add_argument("--step", type=int, default=-1, help="output step (default: the last)")
    ap.add_argument("-o", "--output", default="", help="figure file (default DIR/PREFIX_fault_map.png)")
    a = ap.parse_args()
    run = Run(os.path.dirname(a.run) or ".", os.path.basename(a.run))
    xyz, quads = run.fractures()
    names = fault_names(run)
    which = 1 if not a.fault else (names.index(a.fault) + 1 if a.fault in names else 0)
    if which == 0:
        raise ValueError(f"no fault '{a.fault}' (faults: {', '.join(names)})")
    fault = run.field("fractures/fault", a.step).astype(int)
    keep = fault == which
    status = run.field("fractures/status", a.step).astype(int)[keep]
    slip = run.field("fractures/slip_magnitude", a.step)[keep]
    cff = run.field("fractures/cff", a.step)[keep] / 1e6
    normal = run.field("fractures/normal", a.step)[keep].mean(axis=0)
    strike, _ = plane_axes(normal)
    corners = xyz[quads[keep]]                                 # (elements, 4, 3)
    polys = np.stack([corners @ strike, corners[:, :, 2]], axis=2)
    counts = [int((status == k).sum()) for k in range(3)]
    print(f"fault {names[which - 1]}: {keep.sum()} elements, stick/slip/open {counts[0]}/{counts[1]}/{counts[2]}, "
          f"max slip {slip.max():.3e} m")
    fig, axes = plt.subplots(1, 3, figsize=(12, 4.2), sharey=True)
    panels = [("slip magnitude [m]", slip, "viridis"), ("CFF [MPa]", cff, "coolwarm"), ("status", status, None)]
    for ax, (title, values, cmap) in zip(axes, panels):
        if cmap is None:
            coll = PolyCollection(polys, cmap=ListedColormap(STATUS_COLOURS), edgecolors="0.4", linewidths=0.3)
            coll.set_array(values)
            coll.set_clim(-0.5, 2.5)
            ax.legend(handles=[Patch(color=c, label=n) for n, c in zip(STATUS_NAMES, STATUS_COLOURS)],
                      loc="lower right", fontsize=8)
        else:
            coll = PolyCollection(polys, cmap=cmap, edgecolors="0.4", linewidths=0.3)
            coll.set_array(values)
            if cmap == "coolwarm":
                m = max(abs(values).max(), 1e-12)
                coll.set_clim(-m, m)
            fig.colorbar(coll, ax=ax, shrink=0.8)
        ax.add_collection(coll)
        ax.autoscale_view()
        ax.set_title(title)
        ax.set_xlabel("along strike [m]")
    axes[0].set_ylabel("z [m]")
    t = run.times()[a.step]
    fig.suptitle(f"{run.prefix}: fault '{names[which - 1]}' at load {t:g}, unrolled into its plane")
    fig.tight_layout()
    out = a.output or os.path.join(run.dir, run.prefix + "_fault_map.png")
    fig.savefig(out, dpi=100)
    print(f"figure: {out}")
    return 0


if __name__ == "__main__":
    script_main(main)
