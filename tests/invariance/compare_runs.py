"""Compare the last step of two geoblock runs of the same deck made on
different numbers of ranks: fields matched by node coordinates and cell
centres, relative max-norm difference against a tolerance.

usage: compare_runs.py DIR_A DIR_B PREFIX TOL FIELD [FIELD ...]
Prints one line per field and exits 1 if a difference exceeds TOL."""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "postproc"))
import numpy as np  # noqa: E402
from geoblock_h5 import Run, coordinate_order  # noqa: E402


def main():
    dir_a, dir_b, prefix, tol = sys.argv[1], sys.argv[2], sys.argv[3], float(sys.argv[4])
    a, b = Run(dir_a, prefix), Run(dir_b, prefix)
    ok = len(a.steps) == len(b.steps) and len(a.steps) > 0
    print(f"steps: {len(a.steps)} vs {len(b.steps)}")
    na, nb = coordinate_order(a.coords), coordinate_order(b.coords)
    ca, cb = coordinate_order(a.cell_centres()), coordinate_order(b.cell_centres())
    geo = np.max(np.abs(a.coords[na] - b.coords[nb]))
    print(f"coordinates max difference {geo:.3e}")
    ok = ok and geo < 1e-12
    for name in sys.argv[5:]:
        fa, fb = a.field(name), b.field(name)
        if fa.shape[0] == a.coords.shape[0]:
            fa, fb = fa[na], fb[nb]
        else:
            fa, fb = fa[ca], fb[cb]
        rel = np.max(np.abs(fa - fb)) / max(np.max(np.abs(fa)), 1e-300)
        good = rel <= tol and np.all(np.isfinite(fa)) and np.all(np.isfinite(fb))
        print(f"{name}: relative max difference {rel:.3e} (tol {tol:.1e}) {'ok' if good else 'FAIL'}")
        ok = ok and good
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
