#!/usr/bin/env python3
"""Write a hexahedral mesh of a sphere octant (Gmsh MSH 4.1 ASCII) for Cryer's problem.

usage: make_sphere_octant.py [--level L] [--radius R] [--core C] [--layers NR] OUT.msh

The octant x, y, z >= 0 of the sphere of radius R, split in the standard way
into four blocks: a central cube [0, C R]^3 of n x n x n cells (n = 2^L) and
three blocks of n x n x NR cells between the cube's faces x = C R, y = C R,
z = C R and the sphere (NR radial layers, default 2n: with C = 0.35 the
radial cell size on the axes, 0.65 R / 2n, is close to the cube's, 0.35 R / n;
on the sphere the cells are then about 4 times as wide as thick at most).
A node of the outer blocks at layer m (m = 0 on the cube's face, m = NR on
the sphere) is the point (1 - m/NR) P_c + (m/NR) P_s on the straight line
from its cube point P_c = C R (i, j, k)/n (max(i, j, k) = n) to the sphere
point P_s = R (t_i, t_j, t_k) / |(t_i, t_j, t_k)|, t_i = tan(pi i / (4 n))
(equal angles on the sphere). Every node is made once, from its indices, so
the blocks share their nodes exactly; the nodes of the outer surface lie on
the sphere, those of the symmetry planes on them exactly (a coordinate that
is 0 is written as 0).

Physical groups: the volume "sphere"; the surfaces "xsym" (x = 0), "ysym"
(y = 0), "zsym" (z = 0) and "outer" (the sphere). L = 1, 2, 3, 4 give 56,
448, 3584, 28672 cells. The script checks every cell (det J > 0 at its 8
corners and centre) and prints the smallest scaled Jacobian (det J over the
product of the three edge lengths at a corner: 1 for a cube, 1/sqrt(3) at
the corner (C R, C R, C R) where three blocks meet at 120 degrees).
Needs only numpy.
"""
import argparse
import math
import sys

import numpy as np

# Local faces of the hexahedron, counter-clockwise seen from outside
# (geoblock's mesh.f90 hex_face_nodes, 0-based).
HEX_FACES = [(0, 4, 7, 3), (1, 2, 6, 5), (0, 1, 5, 4), (3, 7, 6, 2), (0, 3, 2, 1), (4, 5, 6, 7)]
# Corners of the reference hexahedron in Gmsh order.
REF = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], dtype=float)
SETS = ["xsym", "ysym", "zsym", "outer"]


def octant(level, radius, core, nr=None):
    """Nodes (n_nodes, 3), hexahedra (n_cells, 8) in Gmsh order and the
    boundary quads of each set {name: (n, 4)}, all 0-based; nr radial layers
    in the outer blocks (default 2n)."""
    n = 2 ** level
    nr = 2 * n if nr is None else nr
    t = np.tan(np.pi / 4 * np.arange(n + 1) / n)
    t[0], t[n] = 0.0, 1.0
    ids = {}
    xyz = []

    def node(m, i, j, k):
        """Id of the node at layer m (0: the central cube) with cube indices i, j, k."""
        key = (m, i, j, k)
        got = ids.get(key)
        if got is None:
            x = core * radius * np.array([i, j, k], dtype=float) / n
            if m > 0:
                d = np.array([t[i], t[j], t[k]])
                ps = radius * d / math.sqrt(float(d @ d))
                x = ps if m == nr else (1.0 - m / nr) * x + (m / nr) * ps
            x[np.array([i, j, k]) == 0] = 0.0
            got = ids[key] = len(xyz)
            xyz.append(x)
        return got

    hexes = []
    for k in range(n):
        for j in range(n):
            for i in range(n):
                hexes.append([node(0, i + a, j + b, k + c) for (a, b, c) in
                              ((0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0),
                               (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1))])
    # outer blocks: axis d is the one whose cube index is n; (p, q) the other two
    for d in range(3):
        p, q = [e for e in range(3) if e != d]
        for m in range(nr):
            for v in range(n):
                for u in range(n):
                    def at(dm, du, dv):
                        idx = [0, 0, 0]
                        idx[d], idx[p], idx[q] = n, u + du, v + dv
                        return node(m + dm, *idx)
                    hexes.append([at(0, 0, 0), at(1, 0, 0), at(1, 1, 0), at(0, 1, 0),
                                  at(0, 0, 1), at(1, 0, 1), at(1, 1, 1), at(0, 1, 1)])
    xyz = np.array(xyz)
    hexes = np.array(hexes)
    # positive orientation: reverse the two faces of a cell whose det J < 0
    neg = _det(xyz[hexes], np.zeros((1, 3)))[:, 0] < 0
    hexes[neg] = hexes[neg][:, [0, 3, 2, 1, 4, 7, 6, 5]]
    on_sphere = np.zeros(len(xyz), dtype=bool)
    for key, v in ids.items():
        on_sphere[v] = key[0] == nr
    quads = {s: [] for s in SETS}
    for h in hexes:
        for f in HEX_FACES:
            qn = h[list(f)]
            for axis in range(3):
                if np.all(xyz[qn, axis] == 0.0):
                    quads[SETS[axis]].append(qn)
            if np.all(on_sphere[qn]):
                quads["outer"].append(qn)
    return xyz, hexes, {s: np.array(v) for s, v in quads.items()}


def _det(x, xi):
    """det J of the cells x (n, 8, 3) at the reference points xi (q, 3): (n, q)."""
    out = np.empty((x.shape[0], xi.shape[0]))
    for k, pt in enumerate(xi):
        f = 1.0 + REF * pt                              # (8, 3)
        dn = np.empty((3, 8))
        dn[0] = REF[:, 0] * f[:, 1] * f[:, 2] / 8
        dn[1] = REF[:, 1] * f[:, 0] * f[:, 2] / 8
        dn[2] = REF[:, 2] * f[:, 0] * f[:, 1] / 8
        jac = np.einsum("ra,nac->nrc", dn, x)           # d x_c / d xi_r
        out[:, k] = np.linalg.det(jac)
    return out


def quality(xyz, hexes):
    """Smallest det J of any cell at its corners and centre [m^3 over the
    reference volume 8], and the smallest scaled Jacobian at the corners."""
    x = xyz[hexes]
    det = _det(x, np.vstack([REF, np.zeros((1, 3))]))
    # scaled Jacobian at corner c: edges to its three neighbours along the axes
    nbr = [(1, 3, 4), (2, 0, 5), (3, 1, 6), (0, 2, 7), (7, 5, 0), (4, 6, 1), (5, 7, 2), (6, 4, 3)]
    sj = np.empty((x.shape[0], 8))
    for c, (a, b, d) in enumerate(nbr):
        e1, e2, e3 = x[:, a] - x[:, c], x[:, b] - x[:, c], x[:, d] - x[:, c]
        vol = np.einsum("ni,ni->n", np.cross(e1, e2), e3)
        sj[:, c] = vol / (np.linalg.norm(e1, axis=1) * np.linalg.norm(e2, axis=1) * np.linalg.norm(e3, axis=1))
    return det.min(), sj.min()


def write_msh(path, xyz, hexes, quads):
    """Gmsh MSH 4.1 ASCII: one volume entity, one surface entity per set."""
    out = ["$MeshFormat", "4.1 0 8", "$EndMeshFormat", "$PhysicalNames", str(len(SETS) + 1)]
    out += ['2 %d "%s"' % (s + 1, name) for s, name in enumerate(SETS)]
    out += ['3 10 "sphere"', "$EndPhysicalNames", "$Entities", "0 0 %d 1" % len(SETS)]
    lo, hi = xyz.min(axis=0), xyz.max(axis=0)
    box = " ".join(repr(float(v)) for v in np.concatenate([lo, hi]))
    out += ["%d %s 1 %d 0" % (s + 1, box, s + 1) for s in range(len(SETS))]
    out += ["1 %s 1 10 %d %s" % (box, len(SETS), " ".join(str(s + 1) for s in range(len(SETS)))),
            "$EndEntities", "$Nodes", "1 %d 1 %d" % (len(xyz), len(xyz)), "3 1 0 %d" % len(xyz)]
    out += [str(i + 1) for i in range(len(xyz))]
    out += ["%.17g %.17g %.17g" % tuple(p) for p in xyz]
    out.append("$EndNodes")
    n_el = len(hexes) + sum(len(q) for q in quads.values())
    out += ["$Elements", "%d %d 1 %d" % (len(SETS) + 1, n_el, n_el)]
    tag = 1
    for s, name in enumerate(SETS):
        out.append("2 %d 3 %d" % (s + 1, len(quads[name])))
        for q in quads[name]:
            out.append(" ".join(str(v) for v in [tag] + list(q + 1)))
            tag += 1
    out.append("3 1 5 %d" % len(hexes))
    for h in hexes:
        out.append(" ".join(str(v) for v in [tag] + list(h + 1)))
        tag += 1
    out.append("$EndElements")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out", help="the .msh file to write")
    ap.add_argument("--level", type=int, default=2, help="n = 2^level cells per block edge (0..6)")
    ap.add_argument("--radius", type=float, default=1.0, help="sphere radius R [m] (> 0)")
    ap.add_argument("--core", type=float, default=0.35, help="half-size of the central cube over R, in (0, 1/sqrt(3))")
    ap.add_argument("--layers", type=int, default=0, help="radial layers of the outer blocks (default 2^(level+1))")
    a = ap.parse_args()
    if not 0 <= a.level <= 6:
        ap.error("--level must lie in 0..6")
    if not (a.radius > 0 and math.isfinite(a.radius)):
        ap.error("--radius must be finite and > 0")
    if not 0 < a.core < 1 / math.sqrt(3):
        ap.error("--core must lie in (0, 1/sqrt(3)): the cube's corner must stay inside the sphere")
    if a.layers < 0:
        ap.error("--layers must be >= 1 (0: the default)")
    xyz, hexes, quads = octant(a.level, a.radius, a.core, a.layers or None)
    det_min, sj_min = quality(xyz, hexes)
    if not det_min > 0:
        sys.exit(f"make_sphere_octant.py: error: a cell has det J = {det_min:.3e} <= 0")
    write_msh(a.out, xyz, hexes, quads)
    print(f"{a.out}: {len(xyz)} nodes, {len(hexes)} hexahedra, quads " +
          ", ".join(f"{s} {len(quads[s])}" for s in SETS) + f"; smallest scaled Jacobian {sj_min:.3f}")


if __name__ == "__main__":
    main()
