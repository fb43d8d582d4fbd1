"""Draw the mesh of a run as a block: the cells on its front (ymin), top
(zmax) and right (xmax) faces coloured by region, with their edges, and the
traces of the faults on those faces.

usage: /usr/bin/python3 postproc/plot_mesh.py DIR/PREFIX [--z-scale S] [-o OUT.png]
Reads DIR/PREFIX_mesh.h5, the region field of the first output step and the
region names of DIR/PREFIX.xdmf; a contact run's faults (DIR/PREFIX_mesh.h5,
/fractures) are drawn in red where they meet the three faces."""
import argparse
import os
import re
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from geoblock_h5 import Run, script_main  # noqa: E402

# the faces of a hexahedron in geoblock's (VTK) node order
HEX_FACES = ((0, 1, 2, 3), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7))


def region_names(run):
    """{id: name} from the region Information element of the run's XDMF file."""
    path = os.path.join(run.dir, run.prefix + ".xdmf")
    try:
        with open(path) as f:
            m = re.search(r'Name="region" Value="[^"]*?:\s*([^"]*)"', f.read())
    except OSError:
        return {}
    if not m:
        return {}
    return {int(k): v.strip() for k, v in re.findall(r"(\d+)\s*=\s*([^,]+)", m.group(1))}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run", help="output directory/prefix of a run")
    ap.add_argument("--z-scale", type=float, default=1.0, help="vertical exaggeration of the drawing")
    ap.add_argument("--elev", type=float, default=22.0, help="view elevation [degrees]")
    ap.add_argument("--azim", type=float, default=-58.0, help="view azimuth [degrees]")
    ap.add_argument("-o", "--output", default="", help="figure file (default DIR/PREFIX_mesh.png)")
    a = ap.parse_args()
    run = Run(os.path.dirname(a.run) or ".", os.path.basename(a.run))
    region = run.field("region", 0).astype(int)
    names = region_names(run)
    lo, hi = run.coords.min(axis=0), run.coords.max(axis=0)
    tol = 1e-9 * np.abs(hi - lo).max()
    on = {"front": (1, lo[1]), "top": (2, hi[2]), "right": (0, hi[0])}
    polys, colours = [], []
    cmap = plt.get_cmap("Set2")
    ids = sorted(set(region.tolist()))
    for c, cell in enumerate(run.conn):
        for face in HEX_FACES:
            pts = run.coords[cell[list(face)]]
            for axis, value in on.values():
                if np.all(np.abs(pts[:, axis] - value) <= tol):
                    polys.append(pts)
                    colours.append(cmap(ids.index(region[c]) % 8))
    polys = np.array(polys)
    polys[:, :, 2] *= a.z_scale
    fig = plt.figure(figsize=(8, 5.6))
    ax = fig.add_subplot(projection="3d")
    ax.computed_zorder = False       # the fault's traces over the faces they lie on
    ax.add_collection3d(Poly3DCollection(polys, facecolors=colours, edgecolors="0.25", linewidths=0.25, zorder=1))
    grid = run.fractures(required=False)
    faults = grid is not None
    if faults:
        fxyz, fquads = grid
    if faults:
        segs = []
        for q in fquads:
            for k in range(4):
                p, r = fxyz[q[k]], fxyz[q[(k + 1) % 4]]
                for axis, value in on.values():
                    if abs(p[axis] - value) <= tol and abs(r[axis] - value) <= tol:
                        segs.append([p, r])
        segs = np.array(segs)
        if len(segs):
            segs[:, :, 2] *= a.z_scale
            ax.add_collection3d(Line3DCollection(segs, colors="red", linewidths=2.2, zorder=2))
    lo_s, hi_s = lo.copy(), hi.copy()
    lo_s[2] *= a.z_scale
    hi_s[2] *= a.z_scale
    ax.set_xlim(lo_s[0], hi_s[0])
    ax.set_ylim(lo_s[1], hi_s[1])
    ax.set_zlim(lo_s[2], hi_s[2])
    ax.set_box_aspect(hi_s - lo_s)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_zlabel("z [m]" + (f" (drawn x {a.z_scale:g})" if a.z_scale != 1.0 else ""))
    ax.view_init(elev=a.elev, azim=a.azim)
    handles = [Patch(color=cmap(ids.index(i) % 8), label=names.get(i, f"region {i}")) for i in ids]
    if faults:
        handles.append(Patch(color="red", label="fault"))
    ax.legend(handles=handles, loc="upper left", fontsize=8)
    ax.set_title(f"{run.prefix}: {len(run.conn)} hexahedra" + (f", {len(fquads)} fault elements" if faults else ""))
    out = a.output or os.path.join(run.dir, run.prefix + "_mesh.png")
    fig.savefig(out, dpi=100, bbox_inches="tight")
    print(f"figure: {out}")
    return 0


if __name__ == "__main__":
    script_main(main)
