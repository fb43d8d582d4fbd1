#!/usr/bin/env python3
"""Write meshes/box_2x2x2.msh, the hand-made Gmsh MSH 4.1 ASCII test mesh.

The unit cube split into 2 x 2 x 2 hexahedra, laid out as Gmsh would store
two boxes stacked in z that share their interface:
  volumes   : 1 = [0,1]^2 x [0,0.5] (physical "rock", tag 10),
              2 = [0,1]^2 x [0.5,1] (physical "cap", tag 20, plus an unnamed
              physical tag 30 that the reader must ignore for cells),
  surfaces  : the two halves of each side, the bottom, the top and the
              internal surface z = 0.5 (physical "fault"); the top also
              carries a second physical group "top",
  curves and points: the box edges and corners; one point ("origin") and one
              curve ("bottom_edge") carry physical groups, with the SAME
              physical tag 1 as "xmin", so a reader must key names by
              (dimension, tag).
Node tags are sparse and not monotone (tag = 2 * ((11 * k) mod 27) + 3 for the
k-th node written); element tags start at 500 with step 3. Every node sits on
the entity of lowest dimension that contains it, as Gmsh does.

Run from the repository root: python3 meshes/make_test_msh.py
"""
import os

H = [0.0, 0.5, 1.0]  # grid coordinates along each axis (2 cells)

# physical groups: (dim, tag, name)
PHYS = [
    (0, 1, "origin"),
    (1, 1, "bottom_edge"),
    (2, 1, "xmin"), (2, 2, "xmax"), (2, 3, "ymin"), (2, 4, "ymax"),
    (2, 5, "zmin"), (2, 6, "zmax"), (2, 7, "fault"), (2, 8, "top"),
    (3, 10, "rock"), (3, 20, "cap"),
]


def main():
    # --- geometric entities -------------------------------------------------
    # points: corners (x, y, z) with z in {0, 0.5, 1}
    points = {}  # (i, j, k) grid index of the corner -> tag
    ptag = 1
    for k in (0, 1, 2):
        for j in (0, 2):
            for i in (0, 2):
                points[(i, j, k)] = ptag
                ptag += 1
    # curves: along x (y, z fixed), along y (x, z fixed), along z (x, y fixed, lower/upper)
    curves = []  # (tag, p0, p1, key) ; key identifies the curve's grid line
    ctag = 1
    for k in (0, 1, 2):
        for j in (0, 2):
            curves.append((ctag, points[(0, j, k)], points[(2, j, k)], ("x", j, k)))
            ctag += 1
        for i in (0, 2):
            curves.append((ctag, points[(i, 0, k)], points[(i, 2, k)], ("y", i, k)))
            ctag += 1
    for (k0, k1) in ((0, 1), (1, 2)):
        for j in (0, 2):
            for i in (0, 2):
                curves.append((ctag, points[(i, j, k0)], points[(i, j, k1)], ("z", i, j, k0)))
                ctag += 1
    ckey = {c[3]: c[0] for c in curves}
    # surfaces: (tag, bbox, physical tags, bounding curves, key)
    surfaces = []
    stag = 101
    for half, (k0, k1) in enumerate(((0, 1), (1, 2))):
        for i, ph in ((0, 1), (2, 2)):  # x = 0 -> xmin, x = 1 -> xmax
            bc = [ckey[("y", i, k0)], ckey[("z", i, 2, k0)], ckey[("y", i, k1)], ckey[("z", i, 0, k0)]]
            surfaces.append((stag, (H[i], 0, H[k0], H[i], 1, H[k1]), [ph], bc, ("x", i, half)))
            stag += 1
        for j, ph in ((0, 3), (2, 4)):
            bc = [ckey[("x", j, k0)], ckey[("z", 2, j, k0)], ckey[("x", j, k1)], ckey[("z", 0, j, k0)]]
            surfaces.append((stag, (0, H[j], H[k0], 1, H[j], H[k1]), [ph], bc, ("y", j, half)))
            stag += 1
    for k, ph in ((0, [5]), (1, [7]), (2, [6, 8])):
        bc = [ckey[("x", 0, k)], ckey[("y", 2, k)], ckey[("x", 2, k)], ckey[("y", 0, k)]]
        surfaces.append((stag, (0, 0, H[k], 1, 1, H[k]), ph, bc, ("z", k)))
        stag += 1
    skey = {s[4]: s[0] for s in surfaces}
    volumes = []
    for half, (k0, k1), ph in ((0, (0, 1), [10]), (1, (1, 2), [20, 30])):
        bs = [skey[("z", k0)], skey[("z", k1)]] + [skey[(a, b, half)] for a in "xy" for b in (0, 2)]
        volumes.append((half + 1, (0, 0, H[k0], 1, 1, H[k1]), ph, bs))

    # --- nodes: each on the entity of lowest dimension containing it ---------
    def entity_of(i, j, k):
        onx, ony = i in (0, 2), j in (0, 2)  # every k lies on a z-plane here
        if onx and ony:
            return (0, points[(i, j, k)])
        if ony:
            return (1, ckey[("x", j, k)])
        if onx:
            return (1, ckey[("y", i, k)])
        return (2, skey[("z", k)])

    blocks = {}  # (dim, tag) -> list of grid indices
    for k in range(3):
        for j in range(3):
            for i in range(3):
                blocks.setdefault(entity_of(i, j, k), []).append((i, j, k))
    order = sorted(blocks)  # points, then curves, then surfaces, by tag
    node_tag = {}
    seq = 0
    for key in order:
        for g in blocks[key]:
            node_tag[g] = 2 * ((11 * seq) % 27) + 3
            seq += 1
    tags = list(node_tag.values())
    assert len(set(tags)) == 27

    def n(i, j, k):
        return node_tag[(i, j, k)]

    # --- elements -------------------------------------------------------------
    eblocks = []  # (dim, entity tag, type, [node tag lists])
    eblocks.append((0, points[(0, 0, 0)], 15, [[n(0, 0, 0)]]))
    eblocks.append((1, ckey[("x", 0, 0)], 1, [[n(0, 0, 0), n(1, 0, 0)], [n(1, 0, 0), n(2, 0, 0)]]))
    for s in surfaces:
        key = s[4]
        quads = []
        if key[0] == "x":
            i, half = key[1], key[2]
            for j in range(2):
                q = [n(i, j, half), n(i, j + 1, half), n(i, j + 1, half + 1), n(i, j, half + 1)]
                quads.append(q if i == 2 else q[::-1])  # outward normal
        elif key[0] == "y":
            j, half = key[1], key[2]
            for i in range(2):
                q = [n(i, j, half), n(i, j, half + 1), n(i + 1, j, half + 1), n(i + 1, j, half)]
                quads.append(q if j == 2 else q[::-1])
        else:
            k = key[1]
            for j in range(2):
                for i in range(2):
                    q = [n(i, j, k), n(i + 1, j, k), n(i + 1, j + 1, k), n(i, j + 1, k)]
                    quads.append(q[::-1] if k == 0 else q)
        eblocks.append((2, s[0], 3, quads))
    for v, k in ((1, 0), (2, 1)):
        hexes = []
        for j in range(2):
            for i in range(2):
                hexes.append([n(i, j, k), n(i + 1, j, k), n(i + 1, j + 1, k), n(i, j + 1, k),
                              n(i, j, k + 1), n(i + 1, j, k + 1), n(i + 1, j + 1, k + 1), n(i, j + 1, k + 1)])
        eblocks.append((3, v, 5, hexes))

    # --- write ------------------------------------------------------------------
    def f(x):
        return repr(float(x)) if x != int(x) else str(int(x))

    out = ["$MeshFormat", "4.1 0 8", "$EndMeshFormat", "$PhysicalNames", str(len(PHYS))]
    out += ['%d %d "%s"' % p for p in PHYS]
    out += ["$EndPhysicalNames", "$Entities",
            "%d %d %d %d" % (len(points), len(curves), len(surfaces), len(volumes))]
    phys_point = {points[(0, 0, 0)]: [1]}
    for g, t in sorted(points.items(), key=lambda x: x[1]):
        ph = phys_point.get(t, [])
        out.append(" ".join([str(t)] + [f(H[c]) for c in g] + [str(len(ph))] + [str(p) for p in ph]))
    phys_curve = {ckey[("x", 0, 0)]: [1]}
    pcoord = {t: g for g, t in points.items()}
    for (t, p0, p1, _) in curves:
        a, b = pcoord[p0], pcoord[p1]
        bb = [H[c] for c in a] + [H[c] for c in b]
        ph = phys_curve.get(t, [])
        out.append(" ".join([str(t)] + [f(x) for x in bb] + [str(len(ph))] + [str(p) for p in ph]
                            + ["2", str(p0), str(-p1)]))
    for (t, bb, ph, bc, _) in surfaces:
        out.append(" ".join([str(t)] + [f(x) for x in bb] + [str(len(ph))] + [str(p) for p in ph]
                            + [str(len(bc))] + [str(c) for c in bc]))
    for (t, bb, ph, bs) in volumes:
        out.append(" ".join([str(t)] + [f(x) for x in bb] + [str(len(ph))] + [str(p) for p in ph]
                            + [str(len(bs))] + [str(s) for s in bs]))
    out += ["$EndEntities", "$Nodes", "%d 27 %d %d" % (len(order), min(tags), max(tags))]
    for key in order:
        g = blocks[key]
        out.append("%d %d 0 %d" % (key[0], key[1], len(g)))
        out += [str(node_tag[x]) for x in g]
        out += [" ".join(f(H[c]) for c in x) for x in g]
    out.append("$EndNodes")
    n_el = sum(len(b[3]) for b in eblocks)
    out += ["$Elements", "%d %d %d %d" % (len(eblocks), n_el, 500, 500 + 3 * (n_el - 1))]
    etag = 500
    for (dim, ent, typ, els) in eblocks:
        out.append("%d %d %d %d" % (dim, ent, typ, len(els)))
        for e in els:
            out.append(" ".join(str(x) for x in [etag] + e))
            etag += 3
    out.append("$EndElements")

    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "box_2x2x2.msh")
    with open(path, "w") as fh:
        fh.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
