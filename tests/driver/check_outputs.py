#!/usr/bin/env python3
"""Checks of the output files a user reads (tests/driver/driver_outputs.sh).

    check_outputs.py stress DIR PREFIX triaxial|shear
        P.xdmf declares 'stress' a cell Tensor6 of n x 6 values, and the
        dataset it points to holds, at ParaView's positions XX YY ZZ XY YZ
        XZ, the exact constant stress of the deck (tests/decks/
        triaxial_probes.nml, shear_box.nml; every load step scaled).
    check_outputs.py probes DIR PREFIX
        P_probes.csv of triaxial_probes.nml: header with units, one row per
        step, values = the exact solution and = the field output.
    check_outputs.py same_csv A.csv B.csv TOL
        the same header and steps, values equal to TOL (relative to the
        largest value of the columns of the same unit).

Prints what it measures; exit status 1 on failure.
"""
import csv
import os
import sys
import xml.etree.ElementTree as ET

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "postproc"))
from geoblock_h5 import Run  # noqa: E402

ORDER = ["XX", "YY", "ZZ", "XY", "YZ", "XZ"]


def exact_stress(case):
    """(XX, YY, ZZ, XY, YZ, XZ) at load factor 1 [Pa]."""
    if case == "triaxial":
        return np.array([1.0e6, -2.0e6, -3.0e6, 0.0, 0.0, 0.0])
    lam = mu = 1.0e9
    a, b, c = 2.0e-3, -1.0e-3, -0.5e-3
    return np.array([lam * c, lam * c, (lam + 2 * mu) * c, 0.0, mu * b, mu * a])


def triaxial_displacement(x, t):
    young, nu = 1.0e9, 0.25
    s = exact_stress("triaxial")[:3]
    eps = (s - nu * (s.sum() - s)) / young
    return eps * np.asarray(x) * t


def stress(directory, prefix, case):
    xdmf = os.path.join(directory, prefix + ".xdmf")
    root = ET.parse(xdmf).getroot()
    steps = [g for g in root.iter("Grid") if g.get("GridType") == "Uniform"]
    worst, ok = 0.0, len(steps) > 0
    for g in steps:
        t = float(g.find("Time").get("Value"))
        att = [a for a in g.findall("Attribute") if a.get("Name") == "stress"]
        if len(att) != 1 or att[0].get("AttributeType") != "Tensor6" or att[0].get("Center") != "Cell":
            print("stress: not one cell Tensor6 attribute 'stress' in " + xdmf)
            return False
        item = att[0].find("DataItem")
        n, ncomp = map(int, item.get("Dimensions").split())
        fname, path = item.text.strip().split(":")
        with h5py.File(os.path.join(directory, fname), "r") as f:
            s = np.array(f[path])
        ok = ok and ncomp == 6 and s.shape == (n, 6)
        want = exact_stress(case) * t
        err = np.abs(s - want).max(axis=0) / np.abs(want).max()
        worst = max(worst, err.max())
    info = {e.get("Name"): e.get("Value") for e in root.iter("Information")}
    ok = ok and "XX YY ZZ XY YZ XZ" in info.get("stress", "")
    print(f"stress ({case}): {len(steps)} steps, Tensor6 n x 6, components " +
          " ".join(f"{k}={v:.3g}" for k, v in zip(ORDER, exact_stress(case))) +
          f" each at its position to {worst:.1e} (tol 1e-9), legend {'ok' if ok else 'missing'}")
    return ok and worst < 1e-9


def read_csv(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    return rows[0], np.array([[float(v) for v in r] for r in rows[1:]])


def probes(directory, prefix):
    head, data = read_csv(os.path.join(directory, prefix + "_probes.csv"))
    run = Run(directory, prefix)
    col = {h: j for j, h in enumerate(head)}
    expect_head = ["step", "load factor [-]"] + \
        [f"inner:{q} [{'m' if q[0] == 'u' else 'Pa'}]" for q in
         ("ux", "uy", "uz", "sxx", "syy", "szz", "sxy", "syz", "sxz")] + \
        [f"line({i}):{q}" for i in (1, 2, 3) for q in ("ux [m]", "szz [Pa]")] + ["lid:uz [m]", "lid:szz [Pa]"]
    ok = head == expect_head and len(data) == 3 and list(data[:, 0]) == [1, 2, 3]
    if not ok:
        print(f"probes: header or steps wrong: {head} / steps {data[:, 0] if len(data) else []}")
        return False
    err_exact, err_field = 0.0, 0.0
    sig = exact_stress("triaxial")
    umax = np.abs(triaxial_displacement([2.0, 3.0, 1.0], 1.0)).max()
    for k, row in enumerate(data):
        t = row[1]
        u = triaxial_displacement([1.3, 2.2, 0.7], t)
        for q, v in zip(("ux", "uy", "uz"), u):
            err_exact = max(err_exact, abs(row[col[f"inner:{q} [m]"]] - v) / umax)
        for q, v in zip(("sxx", "syy", "szz", "sxy", "syz", "sxz"), sig * t):
            err_exact = max(err_exact, abs(row[col[f"inner:{q} [Pa]"]] - v) / 3e6)
        for i, x in enumerate(([0.0, 1.5, 0.5], [1.0, 1.5, 0.5], [2.0, 3.0, 1.0]), start=1):
            err_exact = max(err_exact, abs(row[col[f"line({i}):ux [m]"]] - triaxial_displacement(x, t)[0]) / umax)
        err_exact = max(err_exact, abs(row[col["lid:uz [m]"]] - triaxial_displacement([0, 0, 1.0], t)[2]) / umax)
        # against the field output of the same step (every step is written)
        stress_f = run.field("stress", k)
        u_f = run.field("displacement", k)
        ok = ok and abs(run.times()[k] - t) == 0.0
        cells = np.where(np.all(np.abs(run.cell_centres() - np.array([1.3, 2.2, 0.7])) <
                                np.ptp(run.coords[run.conn], axis=1) / 2, axis=1))[0]
        ok = ok and len(cells) == 1
        names = ("sxx", "syy", "szz", "sxy", "syz", "sxz")
        err_field = max(err_field, max(abs(row[col[f"inner:{q} [Pa]"]] - stress_f[cells[0], j])
                                       for j, q in enumerate(names)) / 3e6)
        top = np.abs(run.coords[:, 2] - 1.0) < 1e-12
        err_field = max(err_field, abs(row[col["lid:uz [m]"]] - u_f[top, 2].mean()) / umax)
        corner = np.where(np.all(np.abs(run.coords - [2.0, 3.0, 1.0]) < 1e-12, axis=1))[0]
        err_field = max(err_field, abs(row[col["line(3):ux [m]"]] - u_f[corner[0], 0]) / umax)
    print(f"probes: {len(head) - 2} columns, {len(data)} steps; against the exact solution {err_exact:.1e}, "
          f"against the field output {err_field:.1e} (tol 1e-9)")
    return ok and err_exact < 1e-9 and err_field < 1e-9


def same_csv(a, b, tol):
    ha, da = read_csv(a)
    hb, db = read_csv(b)
    if ha != hb or da.shape != db.shape or not (da[:, 0] == db[:, 0]).all():
        print("same_csv: headers or steps differ")
        return False
    # a column's scale: the largest value of the columns of its unit (a
    # shear stress that is zero up to round-off is measured against the stress)
    units = [h[h.find("["):] for h in ha]
    big = np.abs(da).max(axis=0)
    scale = np.array([max(big[[j for j, v in enumerate(units) if v == u]].max(), 1e-300) for u in units])
    d = (np.abs(da - db) / scale).max()
    print(f"same_csv: {da.shape[0]} rows x {da.shape[1]} columns, largest relative difference {d:.1e} (tol {tol:g})")
    return d <= tol


def main(argv):
    what = argv[1]
    if what == "stress":
        ok = stress(argv[2], argv[3], argv[4])
    elif what == "probes":
        ok = probes(argv[2], argv[3])
    elif what == "same_csv":
        ok = same_csv(argv[2], argv[3], float(argv[4]))
    else:
        print("unknown check " + what)
        ok = False
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
