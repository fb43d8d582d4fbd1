"""Write the Gmsh mesh of tests/decks/poro_faults_mandel.nml: Mandel's quarter
model 0 <= x <= 1, 0 <= y <= 1 m, one layer of cells THICK m in z, N x N
hexahedra whose node row J follows the dipping line
    y_f(x) = Y0 + (x - 1/2) tan(DIP)
(the rows below and above it spaced evenly between y = 0, y_f and y = 1),
so that the internal physical surface 'glued' (the quads of row J) is a
fault crossing the whole specimen at DIP degrees: Mandel's flow, along x,
crosses it. One physical volume 'rock'; the sides xmin ... zmax. The same
file serves the 'biot' run without the fault (its internal surface is then
an unused set), so both runs have the same cells.

usage: make_mandel_fault_msh.py OUT [--n N] [--j J] [--y0 Y0] [--dip DIP] [--thick THICK]
MSH 4.1 ASCII, written by meshes/make_fault_msh.py's msh_lines (python3 only)."""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "meshes"))
from make_fault_msh import msh_lines  # noqa: E402

PHYS_SURF = [(11, "xmin"), (12, "xmax"), (13, "ymin"), (14, "ymax"), (15, "zmin"), (16, "zmax"), (17, "glued")]
PHYS_VOL = (1, "rock")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("--n", type=int, default=16)
    ap.add_argument("--j", type=int, default=9)
    ap.add_argument("--y0", type=float, default=0.55)
    ap.add_argument("--dip", type=float, default=20.0)
    ap.add_argument("--thick", type=float, default=0.005)
    a = ap.parse_args()
    n, jf = a.n, a.j
    slope = math.tan(math.radians(a.dip))

    def yf(x):
        return a.y0 + (x - 0.5) * slope

    def coords(i, j, k):
        x = i / n
        y = j / jf * yf(x) if j <= jf else yf(x) + (j - jf) / (n - jf) * (1.0 - yf(x))
        return x, y, k * a.thick

    def nt(i, j, k):
        return 1 + i + (n + 1) * (j + (n + 1) * k)

    hexes = [[nt(i, j, 0), nt(i + 1, j, 0), nt(i + 1, j + 1, 0), nt(i, j + 1, 0),
              nt(i, j, 1), nt(i + 1, j, 1), nt(i + 1, j + 1, 1), nt(i, j + 1, 1)]
             for j in range(n) for i in range(n)]
    quads = {name: [] for _, name in PHYS_SURF}
    for j in range(n):
        quads["xmin"].append([nt(0, j, 0), nt(0, j, 1), nt(0, j + 1, 1), nt(0, j + 1, 0)])
        quads["xmax"].append([nt(n, j, 0), nt(n, j + 1, 0), nt(n, j + 1, 1), nt(n, j, 1)])
    for i in range(n):
        quads["ymin"].append([nt(i, 0, 0), nt(i + 1, 0, 0), nt(i + 1, 0, 1), nt(i, 0, 1)])
        quads["ymax"].append([nt(i, n, 0), nt(i, n, 1), nt(i + 1, n, 1), nt(i + 1, n, 0)])
        quads["glued"].append([nt(i, jf, 0), nt(i + 1, jf, 0), nt(i + 1, jf, 1), nt(i, jf, 1)])
    for j in range(n):
        for i in range(n):
            quads["zmin"].append([nt(i, j, 0), nt(i, j + 1, 0), nt(i + 1, j + 1, 0), nt(i + 1, j, 0)])
            quads["zmax"].append([nt(i, j, 1), nt(i + 1, j, 1), nt(i + 1, j + 1, 1), nt(i, j + 1, 1)])

    def bbox(name):
        if name == "glued":
            return (0.0, min(yf(0.0), yf(1.0)), 0.0, 1.0, max(yf(0.0), yf(1.0)), a.thick)
        lo, hi = [0.0, 0.0, 0.0], [1.0, 1.0, a.thick]
        ax = "xyz".index(name[0])
        if name.endswith("min"):
            hi[ax] = lo[ax]
        else:
            lo[ax] = hi[ax]
        return tuple(lo + hi)

    order = [(i, j, k) for k in range(2) for j in range(n + 1) for i in range(n + 1)]
    nodes = [(nt(*ijk), coords(*ijk)) for ijk in order]
    out = msh_lines(nodes, hexes, quads, PHYS_SURF, PHYS_VOL, bbox, (0.0, 0.0, 0.0, 1.0, 1.0, a.thick))
    with open(a.out, "w") as f:
        f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
