#!/usr/bin/env python3
"""Check a run's cell field 'pressure_change' against fault blocks found
here, independently of geoblock: the cells of one region joined through the
faces they share in the written (split) mesh, so that a fault that cuts
through the region separates its two sides.

Usage: check_compartment.py RUN_STEM STEP DP X,Y,Z[:REGION_ID] [...]
  RUN_STEM  output path and prefix (e.g. out/hi24l_small)
  STEP      the output step to read (e.g. 1)
  DP        the expected change in each block [Pa] at that step
  X,Y,Z     a point of each depleted block (as in the deck's &pressure_change)

Passes when every cell of each point's block has DP (to 1e-12 relative),
every other cell 0, and each block is a proper part of its region (the
faults cut the region). Prints the cell counts.
"""
import sys

import h5py
import numpy as np

# the six faces of a hexahedron in Gmsh/VTK node order
HEX_FACES = [(0, 1, 2, 3), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]


def blocks(conn, region):
    """Union-find over the cells: two cells of one region sharing a face."""
    root = np.arange(len(conn))

    def find(c):
        while root[c] != c:
            root[c] = root[root[c]]
            c = root[c]
        return c

    seen = {}
    for c, nodes in enumerate(conn):
        for f in HEX_FACES:
            key = tuple(sorted(nodes[list(f)]))
            other = seen.pop(key, None)
            if other is None:
                seen[key] = c
            elif region[other] == region[c]:
                a, b = find(other), find(c)
                root[max(a, b)] = min(a, b)
    return np.array([find(c) for c in range(len(conn))])


def cell_of(point, x, conn, region):
    """Candidate cells whose bounding box holds the point (then the
    caller requires them to share one block)."""
    lo = x[conn].min(axis=1)
    hi = x[conn].max(axis=1)
    h = (hi - lo).max(axis=1)[:, None]
    inside = np.all((point >= lo - 1e-9 * h) & (point <= hi + 1e-9 * h), axis=1)
    return np.nonzero(inside)[0]


def main():
    if len(sys.argv) < 5:
        print(__doc__)
        return 2
    stem, step, dp = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
    mesh = h5py.File(stem + "_mesh.h5", "r")
    x, conn = mesh["coords"][:], mesh["connectivity"][:]
    out = h5py.File(f"{stem}_{step:04d}.h5", "r")
    region, pc = out["region"][:], out["pressure_change"][:]
    blk = blocks(conn, region)
    expect = np.zeros(len(conn))
    msgs = []
    bad = False
    for arg in sys.argv[4:]:
        p = np.array([float(v) for v in arg.split(",")])
        cand = cell_of(p, x, conn, region)
        # a bounding box may hold the point without the cell doing so: take
        # the candidates' blocks and require the cell whose centre is
        # nearest (the deck's points lie well inside a cell)
        centres = x[conn[cand]].mean(axis=1)
        c = cand[np.argmin(np.linalg.norm(centres - p, axis=1))]
        b = blk[c]
        members = blk == b
        n_region = np.count_nonzero(region == region[c])
        expect[members] = dp
        msgs.append(f"point {arg}: block of {np.count_nonzero(members)} of the region's {n_region} cells")
        if np.count_nonzero(members) >= n_region:
            bad = True
            msgs[-1] += " (FAIL: the block is the whole region)"
    err = np.abs(pc - expect).max() / abs(dp)
    n_changed = np.count_nonzero(pc)
    bad = bad or err > 1e-12
    print(("FAIL " if bad else "") + f"{n_changed} cells changed, largest difference from the blocks found here "
          f"{err:.1e} of |dp| (tol 1e-12); " + "; ".join(msgs))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
