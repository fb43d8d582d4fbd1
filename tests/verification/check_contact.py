#!/usr/bin/env python3
"""Checks of the contact runs of tests/verification/contact.sh.

    check_contact.py stick RUN                 intact solution u = eps x
    check_contact.py same RUN_A RUN_B TOL      fracture fields agree (sorted by centre)
    check_contact.py ranks RUN N               fracture elements owned by N ranks
    check_contact.py orders E1 E2 E3 MIN       observed orders of three errors
    check_contact.py meshio RUN FRICTION_DEG COHESION
                                               RUN_fractures.xdmf read by meshio (every
                                               step) equals the HDF5 fields; legend,
                                               frame, CFF and status consistent

RUN is directory/prefix. Prints what it measures; exit status 1 on failure.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "postproc"))
from geoblock_h5 import Run  # noqa: E402


def load(path):
    return Run(os.path.dirname(path) or ".", os.path.basename(path))


def fracture(run, name):
    return run.field("fractures/" + name)


def stick(path):
    run = load(path)
    young, nu = 1.0e10, 0.25
    sig = np.array([-5.0e6, -5.0e6, -1.0e7])
    eps = (sig - nu * (sig.sum() - sig)) / young
    x = run.coords
    u = run.field("displacement")
    exact = eps * x
    err_u = np.abs(u - exact).max() / np.abs(exact).max()
    err_j = max(np.abs(fracture(run, "slip")).max(), np.abs(fracture(run, "opening")).max()) / np.abs(exact).max()
    n = fracture(run, "normal")
    tn = (n * n * sig).sum(axis=1)
    tv = n * sig                                   # traction vector sigma n
    shear = tv - tn[:, None] * n                   # its tangential part, global frame
    err_t = max(np.abs(fracture(run, "normal_traction") - tn).max(),
                np.abs(fracture(run, "shear_traction") - shear).max(),
                np.abs(fracture(run, "shear_traction_magnitude") - np.linalg.norm(shear, axis=1)).max()) \
        / np.abs(sig).max()
    status = fracture(run, "status")
    print(f"stick: |u - eps x|/|u| {err_u:.2e}, |jump|/|u| {err_j:.2e}, traction error / sigma {err_t:.2e}, "
          f"elements {len(status)}, all stick (0) {bool((status == 0).all())}")
    return err_u < 1e-8 and err_j < 1e-8 and err_t < 1e-8 and (status == 0).all()


def same(a, b, tol):
    ra, rb = load(a), load(b)
    oa = np.lexsort(np.round(fracture(ra, "center"), 9).T[::-1])
    ob = np.lexsort(np.round(fracture(rb, "center"), 9).T[::-1])
    worst = 0.0
    # jumps relative to the largest jump (slip or opening: on a closed,
    # slipping crack the opening is a round-off-sized remainder), tractions
    # to the largest traction
    scale = {"slip": "jump", "opening": "jump", "normal_traction": "traction", "shear_traction": "traction"}
    ref = {"jump": max(np.abs(fracture(ra, "slip")).max(), np.abs(fracture(ra, "opening")).max(), 1e-300),
           "traction": max(np.abs(fracture(ra, "normal_traction")).max(),
                           np.abs(fracture(ra, "shear_traction")).max(), 1e-300)}
    for name in ("slip", "opening", "normal_traction", "shear_traction"):
        fa, fb = fracture(ra, name)[oa], fracture(rb, name)[ob]
        d = np.abs(fa - fb).max() / ref[scale[name]]
        print(f"same: {name} relative difference {d:.2e}")
        worst = max(worst, d)
    sa, sb = fracture(ra, "status")[oa], fracture(rb, "status")[ob]
    print(f"same: statuses equal {bool((sa == sb).all())}")
    return worst <= tol and (sa == sb).all()


def ranks(path, n):
    r = fracture(load(path), "rank")
    got = len(np.unique(r))
    print(f"ranks: fracture elements owned by {got} rank(s): {np.bincount(r)}")
    return got == n


def orders(e1, e2, e3, minimum):
    p1, p2 = np.log2(e1 / e2), np.log2(e2 / e3)
    print(f"orders: errors {e1:.3e} {e2:.3e} {e3:.3e}, observed orders {p1:.2f} {p2:.2f}")
    return p1 >= minimum and p2 >= minimum


def meshio_check(path, friction_deg, cohesion):
    """The fault file as meshio reads it (every step) against the HDF5 fields."""
    import xml.etree.ElementTree as ET
    import meshio
    run = load(path)
    xdmf = path + "_fractures.xdmf"
    info = {e.get("Name"): e.get("Value") for e in ET.parse(xdmf).getroot().iter("Information")}
    legend_ok = info.get("status") == "0 stick, 1 slip, 2 open" and "compression" in info.get("signs", "")
    worst, frame, cff_err, n_slip = 0.0, 0.0, 0.0, 0
    with meshio.xdmf.TimeSeriesReader(xdmf) as reader:
        points, cells = reader.read_points_cells()
        nsteps = reader.num_steps
        times = []
        for k in range(nsteps):
            t, _, cd = reader.read_data(k)
            times.append(t)
            for name in ("slip", "slip_magnitude", "opening", "normal_traction", "shear_traction",
                         "shear_traction_magnitude", "cff", "status", "normal"):
                a = np.asarray(cd[name][0])
                b = fracture(run, name) if k == nsteps - 1 else run.field("fractures/" + name, k)
                worst = max(worst, float(np.abs(a - b).max()))
            slip, n = cd["slip"][0], cd["normal"][0]
            tau, tn = cd["shear_traction"][0], cd["normal_traction"][0]
            frame = max(frame, np.abs((slip * n).sum(axis=1)).max() / max(np.abs(slip).max(), 1e-300),
                        np.abs(np.linalg.norm(slip, axis=1) - cd["slip_magnitude"][0]).max()
                        / max(np.abs(slip).max(), 1e-300))
            cff = np.linalg.norm(tau, axis=1) - (cohesion - np.tan(np.radians(friction_deg)) * tn)
            scale = max(np.abs(tn).max(), 1.0)
            cff_err = max(cff_err, np.abs(cff - cd["cff"][0]).max() / scale)
            st = cd["status"][0]
            n_slip += int((st == 1).sum())
            if not set(np.unique(st)) <= {0, 1, 2} or (cd["cff"][0][st == 1] > 1e-6 * scale).any() \
                    or (cd["cff"][0][st == 0] > 1e-6 * scale).any():
                print(f"meshio: step {k}: statuses {np.unique(st)} or CFF > 0 where not expected")
                return False
    same_times = np.allclose(times, run.times(), rtol=0, atol=0)
    print(f"meshio: {nsteps} steps, {len(points)} points, {sum(len(c.data) for c in cells)} quads, "
          f"max |meshio - h5| {worst:.1e}, slip in plane {frame:.1e}, CFF error {cff_err:.1e}, "
          f"slipping element-steps {n_slip}, legend {legend_ok}, times equal {same_times}")
    return worst == 0.0 and frame < 1e-10 and cff_err < 1e-10 and legend_ok and same_times and n_slip > 0 \
        and nsteps == len(run.steps)


def main(argv):
    what = argv[1]
    if what == "stick":
        ok = stick(argv[2])
    elif what == "same":
        ok = same(argv[2], argv[3], float(argv[4]))
    elif what == "ranks":
        ok = ranks(argv[2], int(argv[3]))
    elif what == "meshio":
        ok = meshio_check(argv[2], float(argv[3]), float(argv[4]))
    elif what == "orders":
        ok = orders(float(argv[2]), float(argv[3]), float(argv[4]), float(argv[5]))
    else:
        print("unknown check " + what)
        ok = False
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
