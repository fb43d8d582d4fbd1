#!/usr/bin/env python3
"""Checks of the contact runs of tests/verification/contact.sh.

    check_contact.py stick RUN                 intact solution u = eps x
    check_contact.py same RUN_A RUN_B TOL      fracture fields agree (sorted by centre)
    check_contact.py ranks RUN N               fracture elements owned by N ranks
    check_contact.py orders E1 E2 E3 MIN       observed orders of three errors

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
    jump = fracture(run, "jump")
    err_j = np.abs(jump).max() / np.abs(exact).max()
    n = fracture(run, "normal")
    t = fracture(run, "traction")
    tn = (n * n * sig).sum(axis=1)
    tv = n * sig                                   # traction vector sigma n
    tt = np.linalg.norm(tv - tn[:, None] * n, axis=1)
    err_t = max(np.abs(t[:, 0] - tn).max(), np.abs(np.hypot(t[:, 1], t[:, 2]) - tt).max()) / np.abs(sig).max()
    status = fracture(run, "status")
    print(f"stick: |u - eps x|/|u| {err_u:.2e}, |jump|/|u| {err_j:.2e}, traction error / sigma {err_t:.2e}, "
          f"elements {len(status)}, all stick {bool((status == 1).all())}")
    return err_u < 1e-8 and err_j < 1e-8 and err_t < 1e-8 and (status == 1).all()


def same(a, b, tol):
    ra, rb = load(a), load(b)
    oa = np.lexsort(np.round(fracture(ra, "center"), 9).T[::-1])
    ob = np.lexsort(np.round(fracture(rb, "center"), 9).T[::-1])
    worst = 0.0
    for name in ("jump", "traction"):
        fa, fb = fracture(ra, name)[oa], fracture(rb, name)[ob]
        d = np.abs(fa - fb).max() / max(np.abs(fa).max(), 1e-300)
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


def main(argv):
    what = argv[1]
    if what == "stick":
        ok = stick(argv[2])
    elif what == "same":
        ok = same(argv[2], argv[3], float(argv[4]))
    elif what == "ranks":
        ok = ranks(argv[2], int(argv[3]))
    elif what == "orders":
        ok = orders(float(argv[2]), float(argv[3]), float(argv[4]), float(argv[5]))
    else:
        print("unknown check " + what)
        ok = False
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
