#!/usr/bin/env python3
"""Tilt the faults of a High Island 24L stand-in mesh, check its cells and
count its unknowns.

usage: make_hi24l.py [--geo GEO] [--vertical] [-o OUT] MESH.msh

MESH.msh is what Gmsh made of meshes/hi24l.geo (MSH 4.1 ASCII): a map mesh
extruded through the layers, so every fault is vertical. The script moves
every node horizontally by

    d(x, y, z) = w(x, y) (z_ref - z) / tan(tilt_dip) e,

e the unit vector towards the azimuth tilt_azimuth, z_ref the depth of the
fault map and w = s(x) s(y), s a smooth step from 0 on a side to 1 at
tilt_taper from it (all four numbers from the .geo). Inside the taper this is one affine
map: planes stay planes, the layers stay horizontal (the geostatic start
needs that), the mesh stays conforming (both sides of a fault move alike),
and every fault gets the dip its strike gives under one shear: a fault
striking at right angles to e dips tilt_dip towards e, one striking along e
stays vertical, the others lie in between. Near the sides the faults turn
back to vertical, so that the block stays a box with vertical sides (rollers
hold them). One shear cannot give faults of one strike opposite dips:
the antithetic faults of the .geo dip the same way as the main set here.
(A move that tilts each fault by its own dip, a harmonic field held on every
fault, was tried and inverted cells at fault tips and T junctions.)

The script refuses a mesh with a cell whose det J is not positive (at the
8 corners and the centre), prints the smallest scaled Jacobian, the dip and
dip azimuth of every fault, and counts what geoblock will see: the cells
per layer, the interface elements, the nodes after the faults are split
(the connected components of the cells around each fault node, the rule of
src/discretization/fault_split.f90), hence n_u = 3 x nodes and n_t = 3 x
interface elements.

--vertical skips the move; -o writes somewhere else than over MESH.msh.
Needs numpy.
"""
import argparse
import math
import os
import re
import sys
import time

import numpy as np

# geoblock's hex faces (mesh.f90 hex_face_nodes, 0-based)
HEX_FACES = np.array([(0, 4, 7, 3), (1, 2, 6, 5), (0, 1, 5, 4), (3, 7, 6, 2), (0, 3, 2, 1), (4, 5, 6, 7)])
REF = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], dtype=float)
SIDES = {"xmin": (1.0, 0.0), "xmax": (1.0, 0.0), "ymin": (0.0, 1.0), "ymax": (0.0, 1.0)}


def fail(msg):
    sys.exit("make_hi24l.py: error: " + msg)


def geo_list(text, name):
    """The numbers of the .geo list NAME[] = {...};"""
    m = re.search(r"^\s*" + name + r"\[\]\s*=\s*\{([^}]*)\}", text, re.M)
    if not m:
        fail("the .geo has no list %s[]" % name)
    return [float(v) for v in m.group(1).replace("\n", " ").split(",")]


def geo_number(text, name):
    m = re.search(r"^\s*" + name + r"\s*=\s*([-+0-9.eE]+)\s*;", text, re.M)
    if not m:
        fail("the .geo has no number %s" % name)
    return float(m.group(1))


class Msh:
    """The parts of a Gmsh MSH 4.1 ASCII file that this script needs; the
    lines are kept so that the file can be written back with new coordinates."""

    def __init__(self, path):
        with open(path) as f:
            L = f.read().split("\n")
        try:
            i = L.index("$PhysicalNames")
        except ValueError:
            fail(path + ": no $PhysicalNames")
        names = {}
        for s in L[i + 2:i + 2 + int(L[i + 1])]:
            d, t, nm = s.split(None, 2)
            names[(int(d), int(t))] = nm.strip('"')
        i = L.index("$Entities")
        c = [int(v) for v in L[i + 1].split()]
        ent = {}
        k = i + 2 + c[0] + c[1]
        for dim, cnt in ((2, c[2]), (3, c[3])):
            for s in L[k:k + cnt]:
                v = s.split()
                n = int(v[7])
                ent[(dim, int(v[0]))] = [names[(dim, int(x))] for x in v[8:8 + n]]
            k += cnt
        # nodes: tag -> index; the line of each node's coordinates
        i = L.index("$Nodes")
        nb, nn = int(L[i + 1].split()[0]), int(L[i + 1].split()[1])
        tags = np.empty(nn, dtype=np.int64)
        xyz = np.empty((nn, 3))
        k, m = i + 2, 0
        for _ in range(nb):
            n = int(L[k].split()[3])
            if n == 0:
                k += 1
                continue
            tags[m:m + n] = [int(s) for s in L[k + 1:k + 1 + n]]
            xyz[m:m + n] = [[float(v) for v in s.split()[:3]] for s in L[k + 1 + n:k + 1 + 2 * n]]
            k += 1 + 2 * n
            m += n
        index = np.full(tags.max() + 1, -1, dtype=np.int64)
        index[tags] = np.arange(nn)
        self.xyz = xyz
        # elements: hexahedra with their region, quads of each set
        i = L.index("$Elements")
        nb = int(L[i + 1].split()[0])
        hexes, regions, quads = [], [], {}
        k = i + 2
        for _ in range(nb):
            d, t, ty, n = (int(v) for v in L[k].split())
            rows = np.array([[int(v) for v in s.split()[1:]] for s in L[k + 1:k + 1 + n]], dtype=np.int64)
            if ty == 5:
                hexes.append(index[rows])
                regions += [ent[(3, t)][0]] * n
            elif ty == 3:
                for nm in ent.get((2, t), []):
                    quads.setdefault(nm, []).append(index[rows])
            elif d >= 2:
                fail("%s: element type %d in entity (%d, %d): geoblock takes hexahedra and quadrangles only "
                     "(Gmsh's recombination left triangles at this size; a slightly different refine "
                     "usually avoids them)" % (path, ty, d, t))
            k += 1 + n
        self.hexes = np.vstack(hexes)
        self.regions = np.array(regions)
        self.quads = {nm: np.vstack(q) for nm, q in quads.items()}



def rebuild_sets(msh, names, tol=1e-3):
    """The fault and side sets as faces of the hexahedra.

    Gmsh's full-quad recombination splits every edge of the map mesh in two,
    but not the edges of a trace embedded inside a map face: the quads Gmsh
    writes for such a fault then span two cell faces each and are no faces
    of any cell. So each fault is taken as a region of its plane (the plane
    of its Gmsh quads, between their smallest and largest along-strike
    coordinate and depth), and its set becomes the vertical cell faces in
    that region; the sides and the top and bottom are the cell faces on the
    planes of the box. Returns {name: (n, 4) node indices}."""
    xyz = msh.xyz
    f = msh.hexes[:, HEX_FACES].reshape(-1, 4)
    key = np.sort(f, axis=1)
    _, first, cnt = np.unique(key, axis=0, return_index=True, return_counts=True)
    lo, hi = xyz.min(axis=0), xyz.max(axis=0)
    sets = {}
    # boundary faces: those of one cell, on a plane of the box
    bnd = f[first[cnt == 1]]
    xb = xyz[bnd]
    for c, axis in enumerate("xyz"):
        for side, v in (("min", lo[c]), ("max", hi[c])):
            sets[axis + side] = bnd[np.all(np.abs(xb[:, :, c] - v) < tol, axis=1)]
    # interior vertical faces
    inner = f[first[cnt == 2]]
    xi = xyz[inner]
    vert = np.ptp(xi[:, :, 2], axis=1) > tol
    inner, xi = inner[vert], xi[vert]
    for nm in names:
        q = msh.xyz[msh.quads[nm]]
        nrm = np.cross(q[0, 2] - q[0, 0], q[0, 3] - q[0, 1])
        nrm[2] = 0.0
        nrm /= np.linalg.norm(nrm)
        tang = np.array([-nrm[1], nrm[0], 0.0])
        c0 = q[:, :, :2].reshape(-1, 2) @ nrm[:2]
        if np.ptp(c0) > tol:
            fail("fault %s: Gmsh's quads are not in one vertical plane" % nm)
        s_q = q.reshape(-1, 3) @ tang
        z_q = q[:, :, 2].ravel()
        on = np.all(np.abs(xi[:, :, :2] @ nrm[:2] - c0.mean()) < tol, axis=1)
        s_i = xi @ tang
        on &= np.all((s_i > s_q.min() - tol) & (s_i < s_q.max() + tol), axis=1)
        on &= np.all((xi[:, :, 2] > z_q.min() - tol) & (xi[:, :, 2] < z_q.max() + tol), axis=1)
        sets[nm] = inner[on]
        area_q = np.sum(np.linalg.norm(np.cross(q[:, 2] - q[:, 0], q[:, 3] - q[:, 1]), axis=1)) / 2
        xf = xyz[sets[nm]]
        area_f = np.sum(np.linalg.norm(np.cross(xf[:, 2] - xf[:, 0], xf[:, 3] - xf[:, 1]), axis=1)) / 2
        if abs(area_f - area_q) > 1e-6 * area_q:
            fail("fault %s: the cell faces on it cover %.4f of its area: the map mesh does not follow its trace"
                 % (nm, area_f / area_q))
    return sets


def write_msh(path, xyz, hexes, regions, sets):
    """A compact MSH 4.1 ASCII file: one volume entity per region, one
    surface entity per set, all nodes (those of the cells, renumbered) in
    one block."""
    used = np.unique(hexes)
    new = np.zeros(len(xyz), dtype=np.int64)
    new[used] = np.arange(1, len(used) + 1)
    rnames = list(dict.fromkeys(regions))
    snames = list(sets)
    out = ["$MeshFormat", "4.1 0 8", "$EndMeshFormat", "$PhysicalNames", str(len(rnames) + len(snames))]
    out += ['2 %d "%s"' % (k + 1, nm) for k, nm in enumerate(snames)]
    out += ['3 %d "%s"' % (k + 1, nm) for k, nm in enumerate(rnames)]
    out += ["$EndPhysicalNames", "$Entities", "0 0 %d %d" % (len(snames), len(rnames))]
    for k, nm in enumerate(snames):
        x = xyz[sets[nm]].reshape(-1, 3)
        out.append("%d %s 1 %d 0" % (k + 1, " ".join("%.10g" % v for v in np.r_[x.min(0), x.max(0)]), k + 1))
    for k, nm in enumerate(rnames):
        x = xyz[hexes[regions == nm]].reshape(-1, 3)
        out.append("%d %s 1 %d 0" % (k + 1, " ".join("%.10g" % v for v in np.r_[x.min(0), x.max(0)]), k + 1))
    out += ["$EndEntities", "$Nodes", "1 %d 1 %d" % (len(used), len(used)), "3 1 0 %d" % len(used)]
    out += [str(i) for i in range(1, len(used) + 1)]
    out += ["%.10g %.10g %.10g" % tuple(p) for p in xyz[used]]
    n_el = len(hexes) + sum(len(v) for v in sets.values())
    out += ["$EndNodes", "$Elements", "%d %d 1 %d" % (len(snames) + len(rnames), n_el, n_el)]
    tag = 1
    for k, nm in enumerate(snames):
        out.append("2 %d 3 %d" % (k + 1, len(sets[nm])))
        for r in new[sets[nm]]:
            out.append("%d %d %d %d %d" % (tag, *r))
            tag += 1
    for k, nm in enumerate(rnames):
        cells = new[hexes[regions == nm]]
        out.append("3 %d 5 %d" % (k + 1, len(cells)))
        for r in cells:
            out.append("%d %d %d %d %d %d %d %d %d" % (tag, *r))
            tag += 1
    out.append("$EndElements")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def det_j(x):
    """det J of the cells x (n, 8, 3) at their 8 corners and centre: (n, 9)."""
    pts = np.vstack([REF, np.zeros((1, 3))])
    out = np.empty((x.shape[0], len(pts)))
    for k, xi in enumerate(pts):
        dn = np.empty((3, 8))
        for a in range(8):
            s = REF[a]
            f = [(1 + s[r] * xi[r]) for r in range(3)]
            dn[0, a] = s[0] * f[1] * f[2] / 8
            dn[1, a] = f[0] * s[1] * f[2] / 8
            dn[2, a] = f[0] * f[1] * s[2] / 8
        out[:, k] = np.linalg.det(np.einsum("ra,nac->nrc", dn, x))
    return out


def scaled_jacobian(x):
    """Smallest det of the three unit edge vectors at each corner: (n,)."""
    nbr = [(1, 3, 4), (2, 0, 5), (3, 1, 6), (0, 2, 7), (7, 5, 0), (4, 6, 1), (5, 7, 2), (6, 4, 3)]
    out = np.full(x.shape[0], np.inf)
    for a, (p, q, r) in enumerate(nbr):
        e = [x[:, b] - x[:, a] for b in (p, q, r)]
        e = [v / np.linalg.norm(v, axis=1)[:, None] for v in e]
        out = np.minimum(out, np.einsum("ni,ni->n", np.cross(e[0], e[1]), e[2]))
    return out


def tilt(xyz, dip, azimuth, z_ref, taper):
    """The horizontal move of the module's docstring: (n, 2)."""
    lo, hi = xyz.min(axis=0), xyz.max(axis=0)
    w = np.ones(len(xyz))
    for c in range(2):     # a product of smooth steps: no kink along the corners' diagonals
        t = np.clip(np.minimum(xyz[:, c] - lo[c], hi[c] - xyz[:, c]) / taper, 0.0, 1.0)
        w *= t * t * (3.0 - 2.0 * t)
    az = math.radians(azimuth)
    shift = w * (z_ref - xyz[:, 2]) / math.tan(math.radians(dip))
    return np.outer(shift, [math.sin(az), math.cos(az)])


def fault_attitude(xyz, quads, lo, hi, margin):
    """Dip [degrees] and dip azimuth of a fault from its quads whose centres
    lie more than margin inside the map (the median of their normals)."""
    x = xyz[quads]
    c = x.mean(axis=1)
    inside = (c[:, 0] > lo[0] + margin) & (c[:, 0] < hi[0] - margin) & \
             (c[:, 1] > lo[1] + margin) & (c[:, 1] < hi[1] - margin)
    if not inside.any():
        return None
    nrm = np.cross(x[inside, 2] - x[inside, 0], x[inside, 3] - x[inside, 1])
    nrm /= np.linalg.norm(nrm, axis=1)[:, None]
    nrm *= np.where(nrm[:, 2] < 0, -1.0, 1.0)[:, None]     # upward normals
    n = np.median(nrm, axis=0)
    n /= np.linalg.norm(n)
    dip = math.degrees(math.acos(min(1.0, abs(n[2]))))
    azimuth = math.degrees(math.atan2(n[0], n[1])) % 360.0 if dip > 1e-6 else float("nan")
    return dip, azimuth


def split_count(hexes, fault_quads):
    """Nodes added when the fault quads are split (fault_split.f90's rule)."""
    fkeys = set(tuple(sorted(q)) for q in fault_quads)
    on_fault = np.zeros(hexes.max() + 1, dtype=bool)
    on_fault[np.unique(fault_quads)] = True
    parent = {}

    def find(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    cells = np.where(on_fault[hexes].any(axis=1))[0]
    owner = {}
    for c in cells:
        for n in hexes[c]:
            if on_fault[n]:
                parent[(n, c)] = (n, c)
        for lf in HEX_FACES:
            key = tuple(sorted(hexes[c, lf]))
            if key in fkeys:
                continue
            other = owner.get(key)
            if other is None:
                owner[key] = c
                continue
            for n in key:
                if on_fault[n]:
                    a, b = find((n, c)), find((n, other))
                    if a != b:
                        parent[a] = b
    comps = {}
    for k in parent:
        comps.setdefault(k[0], set()).add(find(k))
    return sum(len(s) - 1 for s in comps.values())


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("mesh")
    ap.add_argument("--geo", default=None, help="the .geo with tilt_dip, tilt_azimuth and z_ref (default: "
                    "hi24l.geo beside this script)")
    ap.add_argument("--vertical", action="store_true", help="keep the faults vertical (no move)")
    ap.add_argument("-o", "--out", default=None, help="output file (default: over MESH)")
    a = ap.parse_args()
    geo = a.geo or os.path.join(os.path.dirname(os.path.abspath(__file__)), "hi24l.geo")
    with open(geo) as f:
        text = f.read()
    dip, azimuth = geo_number(text, "tilt_dip"), geo_number(text, "tilt_azimuth")
    z_ref, taper = geo_number(text, "z_ref"), geo_number(text, "tilt_taper")
    nf = len(geo_list(text, "FAZ"))
    t0 = time.time()
    msh = Msh(a.mesh)
    print("read %s: %d hexahedra (%.1f s)" % (a.mesh, len(msh.hexes), time.time() - t0))
    names = ["f%02d" % (j + 1) for j in range(nf)]
    for nm in names + list(SIDES) + ["zmin", "zmax"]:
        if nm not in msh.quads:
            fail("the mesh has no surface set %s" % nm)
    sets = rebuild_sets(msh, names)
    xyz = msh.xyz.copy()
    if not det_j(xyz[msh.hexes]).min() > 0:
        fail("Gmsh's mesh has a cell with det J <= 0")
    if not a.vertical and dip < 90.0:
        d = tilt(xyz, dip, azimuth, z_ref, taper)
        xyz[:, :2] += d
        print("tilt: dip %g towards N%gE about z = %g m, tapered over %g m from the sides; largest move %.1f m" %
              (dip, azimuth, z_ref, taper, np.abs(d).max()))
    x = xyz[msh.hexes]
    dj = det_j(x)
    if not dj.min() > 0:
        bad = np.where(dj.min(axis=1) <= 0)[0]
        fail("%d cells have det J <= 0 after the tilt (first at %s)" % (len(bad), x[bad[0]].mean(axis=0)))
    sj = scaled_jacobian(x)
    print("cells: det J > 0 at every corner and centre; scaled Jacobian: smallest %.3f, %.2f%% of the cells "
          "below 0.3" % (sj.min(), 100.0 * np.mean(sj < 0.3)))
    lo, hi = xyz.min(axis=0), xyz.max(axis=0)
    print("fault  quads  dip  dip azimuth (away from the tapered sides)")
    for nm in names:
        att = fault_attitude(xyz, sets[nm], lo, hi, taper)
        if att is None:
            print("%s  %5d  (within %g m of a side)" % (nm, len(sets[nm]), taper))
        else:
            print("%s  %5d  %4.1f  %5.1f" % (nm, len(sets[nm]), att[0], att[1]))
    # what geoblock will see
    used = np.unique(msh.hexes)
    fq = np.vstack([sets[nm] for nm in names])
    added = split_count(msh.hexes, fq)
    print("cells per layer:", ", ".join("%s %d" % (r, np.sum(msh.regions == r))
                                        for r in dict.fromkeys(msh.regions)))
    n_nodes = len(used) + added
    print("hexahedra %d, nodes %d (+%d by the split = %d), interface elements %d" %
          (len(msh.hexes), len(used), added, n_nodes, len(fq)))
    print("n_u = %d, n_t = %d, total %d" % (3 * n_nodes, 3 * len(fq), 3 * n_nodes + 3 * len(fq)))
    out = a.out or a.mesh
    write_msh(out, xyz, msh.hexes, msh.regions, sets)
    print("wrote", out)


if __name__ == "__main__":
    main()
