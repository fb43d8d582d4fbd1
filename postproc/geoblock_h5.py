"""Read geoblock's HDF5/XDMF output.

A run with output prefix P in directory D writes D/P_mesh.h5 (coords,
connectivity), one D/P_NNNN.h5 per output time (fields, attribute 'time') and
D/P.xdmf (the index ParaView opens). Needs numpy and h5py (Debian packages
python3-numpy, python3-h5py).
"""
import glob
import os
import re

import h5py
import numpy as np


class Run:
    """The output of one run: mesh and the list of steps."""

    def __init__(self, directory, prefix):
        self.dir = directory
        self.prefix = prefix
        mesh = os.path.join(directory, prefix + "_mesh.h5")
        if not os.path.exists(mesh):
            raise FileNotFoundError(f"no geoblock mesh file {mesh}")
        with h5py.File(mesh, "r") as f:
            self.coords = np.array(f["coords"])          # (n_nodes, 3)
            self.conn = np.array(f["connectivity"])      # (n_cells, 8), 0-based
        pat = re.compile(re.escape(prefix) + r"_(\d{4,})\.h5$")
        steps = []
        for path in glob.glob(os.path.join(directory, prefix + "_*.h5")):
            m = pat.search(os.path.basename(path))
            if m:
                steps.append((int(m.group(1)), path))
        self.steps = [p for _, p in sorted(steps)]

    def times(self):
        out = []
        for p in self.steps:
            with h5py.File(p, "r") as f:
                out.append(float(f.attrs["time"]))
        return np.array(out)

    def field(self, name, step=-1):
        """Field array of a step (nodes or cells first, components second)."""
        with h5py.File(self.steps[step], "r") as f:
            return np.array(f[name])

    def cell_centres(self):
        return self.coords[self.conn].mean(axis=1)


def coordinate_order(points, decimals=9):
    """Permutation that sorts points lexicographically by rounded coordinates,
    so that runs with different partitions (and global numberings) compare."""
    p = np.round(np.asarray(points), decimals)
    return np.lexsort((p[:, 2], p[:, 1], p[:, 0]))
