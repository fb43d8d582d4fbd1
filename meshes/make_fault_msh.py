#!/usr/bin/env python3
"""Write meshes/fault_tip.msh, a small Gmsh MSH 4.1 ASCII mesh with a fracture.

The unit cube in 4 x 4 x 4 hexahedra on a non-uniform grid, one volume
(physical "rock"), the six sides as physical surfaces xmin ... zmax, and an
internal physical surface "fault" on the plane x = 0.5 that covers
y in [0.25, 1] and z in [0, 0.5]: it reaches the sides y = 1 and z = 0 and
ends inside the domain along two tip lines (y = 0.25 and z = 0.5). Its 3 x 2
quads share their nodes with the hexahedra on both sides (a conforming mesh,
as Gmsh writes an embedded surface); geoblock splits them.

Expected after splitting the fault: 6 interface elements; of the 12 nodes on
the fault, the 6 on the tip lines keep one copy and the other 6 are split, so
the mesh grows from 125 to 131 nodes.

The layout is simpler than Gmsh's own (no points or curves, all nodes in the
volume's node block, node tags in a shuffled order), which the MSH 4.1 format
allows and which a reader must accept. python3 only (numpy is not needed).

Run from the repository root: python3 meshes/make_fault_msh.py
"""
import os

X = [0.0, 0.3, 0.5, 0.8, 1.0]
Y = [0.0, 0.25, 0.5, 0.75, 1.0]
Z = [0.0, 0.25, 0.5, 0.75, 1.0]
N = 4  # cells per axis
FAULT_I = 2  # x index of the fault plane (x = 0.5)
FAULT_J = (1, 4)  # y cell range [j0, j1): y in [0.25, 1]
FAULT_K = (0, 2)  # z cell range: z in [0, 0.5]

PHYS_SURF = [(11, "xmin"), (12, "xmax"), (13, "ymin"), (14, "ymax"), (15, "zmin"), (16, "zmax"), (17, "fault")]
PHYS_VOL = (1, "rock")


def grid_index(i, j, k):
    return i + (N + 1) * (j + (N + 1) * k)


def main():
    n_nodes = (N + 1) ** 3
    # node tags: a fixed permutation of 1..n (7 is coprime with 125), plus 100
    tag = [100 + 1 + (7 * g) % n_nodes for g in range(n_nodes)]

    def nt(i, j, k):
        return tag[grid_index(i, j, k)]

    hexes = []
    for k in range(N):
        for j in range(N):
            for i in range(N):
                hexes.append([nt(i, j, k), nt(i + 1, j, k), nt(i + 1, j + 1, k), nt(i, j + 1, k),
                              nt(i, j, k + 1), nt(i + 1, j, k + 1), nt(i + 1, j + 1, k + 1), nt(i, j + 1, k + 1)])
    quads = {name: [] for _, name in PHYS_SURF}
    for k in range(N):
        for j in range(N):
            quads["xmin"].append([nt(0, j, k), nt(0, j, k + 1), nt(0, j + 1, k + 1), nt(0, j + 1, k)])
            quads["xmax"].append([nt(N, j, k), nt(N, j + 1, k), nt(N, j + 1, k + 1), nt(N, j, k + 1)])
    for k in range(N):
        for i in range(N):
            quads["ymin"].append([nt(i, 0, k), nt(i + 1, 0, k), nt(i + 1, 0, k + 1), nt(i, 0, k + 1)])
            quads["ymax"].append([nt(i, N, k), nt(i, N, k + 1), nt(i + 1, N, k + 1), nt(i + 1, N, k)])
    for j in range(N):
        for i in range(N):
            quads["zmin"].append([nt(i, j, 0), nt(i, j + 1, 0), nt(i + 1, j + 1, 0), nt(i + 1, j, 0)])
            quads["zmax"].append([nt(i, j, N), nt(i + 1, j, N), nt(i + 1, j + 1, N), nt(i, j + 1, N)])
    for k in range(*FAULT_K):
        for j in range(*FAULT_J):
            i = FAULT_I
            quads["fault"].append([nt(i, j, k), nt(i, j + 1, k), nt(i, j + 1, k + 1), nt(i, j, k + 1)])

    def bbox(name):
        if name == "fault":
            return (X[FAULT_I], Y[FAULT_J[0]], Z[FAULT_K[0]], X[FAULT_I], Y[FAULT_J[1]], Z[FAULT_K[1]])
        axis, side = name[0], name[1:]
        lo, hi = [0.0, 0.0, 0.0], [1.0, 1.0, 1.0]
        a = "xyz".index(axis)
        if side == "min":
            hi[a] = 0.0
        else:
            lo[a] = 1.0
        return tuple(lo + hi)

    order = [(i, j, k) for k in range(N + 1) for j in range(N + 1) for i in range(N + 1)]
    nodes = [(nt(*ijk), (X[ijk[0]], Y[ijk[1]], Z[ijk[2]])) for ijk in order]
    out = msh_lines(nodes, hexes, quads, PHYS_SURF, PHYS_VOL, bbox, (0.0, 0.0, 0.0, 1.0, 1.0, 1.0))
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "fault_tip.msh")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")
    print("wrote", path)


def msh_lines(nodes, hexes, quads, phys_surf, phys_vol, bbox, vol_bbox):
    """The lines of an MSH 4.1 ASCII file: nodes [(tag, (x, y, z))] in one
    block of the volume, the hexahedra (lists of 8 node tags), quads
    {surface name: [4 node tags]} for each (tag, name) of phys_surf, one
    physical volume phys_vol = (tag, name); bbox(name) and vol_bbox the
    entities' bounding boxes. Also used by
    tests/verification/make_mandel_fault_msh.py."""
    tags = [t for t, _ in nodes]
    out = []
    out += ["$MeshFormat", "4.1 0 8", "$EndMeshFormat"]
    out += ["$PhysicalNames", str(len(phys_surf) + 1)]
    out += ['2 %d "%s"' % (t, name) for t, name in phys_surf]
    out += ['3 %d "%s"' % phys_vol, "$EndPhysicalNames"]
    out += ["$Entities", "0 0 %d 1" % len(phys_surf)]
    for e, (t, name) in enumerate(phys_surf, start=1):
        out.append("%d %s 1 %d 0" % (e, " ".join("%.17g" % v for v in bbox(name)), t))
    out.append("1 %s 1 %d %d %s" % (" ".join("%.17g" % v for v in vol_bbox), phys_vol[0], len(phys_surf) - 1,
                                    " ".join(str(e) for e in range(1, len(phys_surf)))))
    out.append("$EndEntities")
    out += ["$Nodes", "1 %d %d %d" % (len(nodes), min(tags), max(tags)), "3 1 0 %d" % len(nodes)]
    out += [str(t) for t in tags]
    out += ["%.17g %.17g %.17g" % x for _, x in nodes]
    out.append("$EndNodes")
    n_elem = len(hexes) + sum(len(q) for q in quads.values())
    out += ["$Elements", "%d %d 1 %d" % (len(phys_surf) + 1, n_elem, n_elem)]
    etag = 1
    for e, (_, name) in enumerate(phys_surf, start=1):
        out.append("2 %d 3 %d" % (e, len(quads[name])))
        for q in quads[name]:
            out.append("%d %s" % (etag, " ".join(map(str, q))))
            etag += 1
    out.append("3 1 5 %d" % len(hexes))
    for h in hexes:
        out.append("%d %s" % (etag, " ".join(map(str, h))))
        etag += 1
    out.append("$EndElements")
    return out


if __name__ == "__main__":
    main()
