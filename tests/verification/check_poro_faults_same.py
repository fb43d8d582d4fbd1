#!/usr/bin/env python3
"""Two runs of one 'poromechanics_faults' deck (tests/verification/poro_faults.sh:
MUMPS against FGMRES with the block preconditioner, or 1 against 2 or 3
ranks): at every step, every field in physical units, the largest difference
relative to the field's largest magnitude over the run.

usage: check_poro_faults_same.py RUN_A RUN_B TOL LABEL
RUN is the output directory plus prefix. Prints one line per field and the
worst; records the worst (tests/common/vreport.sh); exit 1 above TOL."""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "postproc"))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from geoblock_h5 import Run, coordinate_order  # noqa: E402
from vreport import record  # noqa: E402

MESH = ["displacement", "pressure", "darcy_velocity", "stress"]
FRACTURES = ["pressure", "opening", "slip", "normal_traction", "shear_traction", "leakoff", "status"]


def load(path):
    return Run(os.path.dirname(path) or ".", os.path.basename(path))


def main():
    a, b = load(sys.argv[1]), load(sys.argv[2])
    tol, label = float(sys.argv[3]), sys.argv[4]
    if len(a.steps) != len(b.steps) or len(a.steps) == 0:
        print(f"FAIL steps {len(a.steps)} vs {len(b.steps)}")
        sys.exit(1)
    ca, cb = coordinate_order(a.cell_centres()), coordinate_order(b.cell_centres())
    fa0 = np.asarray(a.field("fractures/center", 0))
    fb0 = np.asarray(b.field("fractures/center", 0))
    ea, eb = coordinate_order(fa0), coordinate_order(fb0)
    worst, ok = 0.0, True
    for name in MESH + ["fractures/" + n for n in FRACTURES]:
        diff, mag = 0.0, 0.0
        for s in range(len(a.steps)):
            fa, fb = np.asarray(a.field(name, s)), np.asarray(b.field(name, s))
            if name.startswith("fractures/"):
                fa, fb = fa[ea], fb[eb]
            elif fa.shape[0] == a.coords.shape[0]:
                # by cell and local node: a fault's two sides have nodes at
                # the same coordinates
                fa, fb = fa[a.conn[ca]], fb[b.conn[cb]]
            else:
                fa, fb = fa[ca], fb[cb]
            if not (np.all(np.isfinite(fa)) and np.all(np.isfinite(fb))):
                ok = False
            diff = max(diff, float(np.abs(fa - fb).max()))
            mag = max(mag, float(np.abs(fa).max()))
        rel = diff / mag if mag > 0 else diff
        worst = max(worst, rel)
        print(f"{name}: largest difference {rel:.2e} of its largest magnitude {mag:.3e}")
    ok = ok and worst <= tol
    print(f"{'ok' if ok else 'FAIL'} {label}: every field within {worst:.2e} (tol {tol:.0e})")
    record(label, "largest difference of a field, relative to its largest magnitude", worst, tol, passed=ok)
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
