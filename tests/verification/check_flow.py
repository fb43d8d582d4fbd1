#!/usr/bin/env python3
"""Checks of physics = 'fracture_flow' runs (tests/verification/fracture_flow.sh).

    check_flow.py mass RUN Q TOL      every step: change of fracture volume plus
                                      compressibility storage = Q dt (relative to Q dt)
    check_flow.py sneddon RUN Q LZ TOL  mean pressure at the last step against
                                      E (Q/LZ) t / (2 pi (1 - nu^2) b^2)
    check_flow.py same RUN1 RUN2 TOL  pressure and opening of two runs (by element centre)
RUN is the output directory plus prefix. Prints one line; exit 1 on a failure.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "postproc"))
from geoblock_h5 import Run  # noqa: E402


def load(path):
    return Run(os.path.dirname(path) or ".", os.path.basename(path))


def fields(run, step):
    f = lambda n: np.asarray(run.field("fractures/" + n, step))  # noqa: E731
    return f("center"), f("opening"), f("pressure"), f("aperture"), f("area")


def mass(path, q, tol):
    run = load(path)
    par = run.parameters()
    cf = float(par["fracture_flow"][0]["compressibility"])
    times = run.times()
    worst = 0.0
    _, g0, p0, _, area = fields(run, 0)
    for k in range(1, len(times)):
        _, g, p, a, _ = fields(run, k)
        dv = np.sum(area * (g - g0)) + np.sum(area * a * cf * (p - p0))
        inj = q * (times[k] - times[k - 1])
        if inj > 0:
            worst = max(worst, abs(dv - inj) / inj)
        g0, p0 = g, p
    print(f"mass: {len(times) - 1} steps, largest |dV - Q dt| / (Q dt) {worst:.2e}")
    return worst <= tol


def sneddon(path, q, lz, tol):
    run = load(path)
    par = run.parameters()
    e, nu = float(par["material"][0]["young"]), float(par["material"][0]["poisson"])
    centre, _, p, _, area = fields(run, -1)
    b = 0.5 * np.sum(area) / lz                        # half-length from the fracture's area
    t = run.times()[-1]
    exact = e * (q / lz) * t / (2.0 * np.pi * (1.0 - nu**2) * b**2)
    mean = np.sum(area * p) / np.sum(area)
    err = abs(mean - exact) / exact
    spread = (p.max() - p.min()) / exact
    print(f"sneddon: t = {t:g} s, mean p {mean:.6e} Pa, exact {exact:.6e} Pa, error {err:.3e}, spread {spread:.2e}")
    return err <= tol


def same(a, b, tol):
    ra, rb = load(a), load(b)
    ca, ga, pa, _, _ = fields(ra, -1)
    cb, gb, pb, _, _ = fields(rb, -1)
    oa = np.lexsort(np.round(ca, 9).T[::-1])
    ob = np.lexsort(np.round(cb, 9).T[::-1])
    dp = np.abs(pa[oa] - pb[ob]).max() / np.abs(pa).max()
    dg = np.abs(ga[oa] - gb[ob]).max() / np.abs(ga).max()
    print(f"same: pressure {dp:.2e}, opening {dg:.2e}")
    return max(dp, dg) <= tol


if __name__ == "__main__":
    if len(sys.argv) < 2 or sys.argv[1] in ("-h", "--help"):
        print(__doc__)
        sys.exit(0)
    cmd, args = sys.argv[1], sys.argv[2:]
    if cmd == "mass":
        ok = mass(args[0], float(args[1]), float(args[2]))
    elif cmd == "sneddon":
        ok = sneddon(args[0], float(args[1]), float(args[2]), float(args[3]))
    elif cmd == "same":
        ok = same(args[0], args[1], float(args[2]))
    else:
        sys.exit(f"check_flow.py: unknown check '{cmd}'")
    sys.exit(0 if ok else 1)
