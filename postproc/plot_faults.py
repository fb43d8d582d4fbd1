#!/usr/bin/env python3
"""Draw the faults of a geoblock contact run in 3D, coloured by status or by
a fault field, and print per fault its stick/slip/open counts and largest
slip: which faults reactivate, and where.

    python3 postproc/plot_faults.py out/hi24l                  (last step)
    python3 postproc/plot_faults.py out/hi24l --step 3 --field slip_magnitude
    python3 postproc/plot_faults.py out/hi24l -o faults.png --elev 35 --azim -60

The argument is the output directory plus prefix (as in &output). Fields:
'status' (stick grey, slip red, open blue: the default) or any scalar of the
fractures grid ('slip_magnitude', 'normal_traction', 'shear_traction_magnitude',
'opening', 'cff', ...; with a colour bar). --z-scale stretches z (a reservoir
a few hundred metres thick under kilometres of map). --fault f01,f07 draws
those faults only. Writes PREFIX_faults.png beside the output unless -o
says otherwise. Needs numpy, h5py and matplotlib.
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from geoblock_h5 import Run, read_parameters, script_main  # noqa: E402

STATUS_NAMES = ("stick", "slip", "open")
STATUS_COLOURS = ((0.72, 0.72, 0.72), (0.85, 0.15, 0.1), (0.15, 0.35, 0.85))


def fault_names(run):
    """The &fault names of the run in the order of the 'fault' field (1-based)."""
    par = read_parameters(os.path.join(run.dir, run.prefix + "_parameters.nml"))
    return [f["name"] for f in par.get("fault", [])]


def summary(names, fault, status, slip):
    lines = []
    for k, name in enumerate(names, start=1):
        on = fault == k
        if not on.any():
            continue
        counts = [int(np.sum(status[on] == s)) for s in range(3)]
        lines.append(f"fault {name:>10}: {on.sum():7d} elements, stick/slip/open "
                     f"{counts[0]}/{counts[1]}/{counts[2]}, max slip {slip[on].max():.3e} m")
    return lines


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("run", help="output directory/prefix")
    ap.add_argument("--step", type=int, default=-1, help="output step (default: the last)")
    ap.add_argument("--field", default="status")
    ap.add_argument("--fault", default="", help="comma-separated fault names to draw (default: all)")
    ap.add_argument("--z-range", default="",
                    help="ZMIN,ZMAX [m]: draw only the elements whose centre lies in this depth window "
                         "(e.g. a reservoir interval; default: all)")
    ap.add_argument("--z-scale", type=float, default=1.0, help="vertical exaggeration of the drawing")
    ap.add_argument("--elev", type=float, default=30.0, help="view elevation [degrees]")
    ap.add_argument("--azim", type=float, default=-60.0, help="view azimuth [degrees]")
    ap.add_argument("-o", "--output", default="")
    a = ap.parse_args()
    run = Run(os.path.dirname(a.run) or ".", os.path.basename(a.run))
    xyz, quads = run.fractures()
    status = run.field("fractures/status", a.step).astype(int)
    fault = run.field("fractures/fault", a.step).astype(int)
    slip = run.field("fractures/slip_magnitude", a.step)
    names = fault_names(run)
    for line in summary(names, fault, status, slip):
        print(line)
    keep = np.ones(len(quads), bool)
    if a.fault:
        wanted = [names.index(n) + 1 for n in a.fault.split(",") if n in names]
        keep = np.isin(fault, wanted)
    if a.z_range:
        try:
            zmin, zmax = sorted(float(v) for v in a.z_range.split(","))
        except ValueError:
            raise ValueError(f"--z-range '{a.z_range}': expected ZMIN,ZMAX in metres") from None
        zc = xyz[quads][:, :, 2].mean(axis=1)
        keep &= (zc >= zmin) & (zc <= zmax)
        if not keep.any():
            raise ValueError(f"--z-range {a.z_range}: no fault element has its centre in it")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection
    polys = xyz[quads[keep]].copy()
    polys[:, :, 2] *= a.z_scale
    fig = plt.figure(figsize=(9, 7))
    ax = fig.add_subplot(projection="3d")
    if a.field == "status":
        colours = np.array(STATUS_COLOURS)[status[keep]]
        coll = Poly3DCollection(polys, facecolors=colours, edgecolors="none")
        from matplotlib.patches import Patch
        ax.legend(handles=[Patch(color=c, label=n) for n, c in zip(STATUS_NAMES, STATUS_COLOURS)], loc="upper left")
    else:
        values = run.field("fractures/" + a.field, a.step)[keep]
        coll = Poly3DCollection(polys, edgecolors="none", cmap="viridis")
        coll.set_array(values)
        fig.colorbar(coll, ax=ax, shrink=0.6, label=a.field)
    ax.add_collection3d(coll)
    lo, hi = polys.reshape(-1, 3).min(axis=0), polys.reshape(-1, 3).max(axis=0)
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_zlim(lo[2], hi[2])
    ax.set_box_aspect(hi - lo)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_zlabel("z [m]" + (f" (drawn x {a.z_scale:g})" if a.z_scale != 1.0 else ""))
    if a.z_scale != 1.0:
        # the ticks name true depths, at round values of them
        from matplotlib.ticker import MaxNLocator
        ticks = [t for t in MaxNLocator(5).tick_values(lo[2] / a.z_scale, hi[2] / a.z_scale)
                 if lo[2] <= t * a.z_scale <= hi[2]]
        ax.set_zticks([t * a.z_scale for t in ticks])
        ax.set_zticklabels([f"{t:g}" for t in ticks])
    ax.view_init(elev=a.elev, azim=a.azim)
    t = run.times()[a.step]
    ax.set_title(f"{run.prefix}: faults, {a.field}, load {t:g}")
    out = a.output or os.path.join(run.dir, run.prefix + "_faults.png")
    fig.savefig(out, dpi=130, bbox_inches="tight")
    print(f"figure: {out}")
    return 0


if __name__ == "__main__":
    script_main(main)
