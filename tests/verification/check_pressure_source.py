#!/usr/bin/env python3
"""A pressure-controlled &source at steady state against the closed form of
postproc/analytical.py's SourceColumn (tests/verification/pressure_source.sh,
deck tests/decks/pressure_source.nml): a column along z closed at its
bottom, held at p_b at its top, whose region of cells below z = a takes
I |c| (p_w - p_c).

usage: check_pressure_source.py steady RUN [--tol T] [--balance B] [--label L]
       check_pressure_source.py order RUN_H RUN_H2 [--min-order Q] [--label L]
       check_pressure_source.py same RUN_A RUN_B [--tol T] [--label L]
RUN is the output directory plus prefix. The parameters (p_w, I, p_b, k/mu,
the column, a) come from the run's resolved deck. At the last step:
  field    every cell's pressure against the closed form's mean over the
           cell, the largest difference relative to |p_w - p_b| (<= T);
  rate     the probe file's '<name>:rate [m3/s]' against Q times the
           column's section (relative, <= T);
  balance  the outflow through the top (the top cells' Darcy velocity times
           their section) against that rate (relative, <= B: at steady state
           the fluid the source gives leaves through the top);
  fracture (runs with fractures) every element's pressure against the
           closed form at its height (relative to |p_w - p_b|, <= T).
order: the field and rate errors of two runs with h and h/2, and their
observed orders (>= Q).
same: two runs of one deck (other ranks, another solver): the pressures of
every cell and the source's rate at every step, the largest difference
relative to the largest magnitude (<= T). Prints one line per check; records them
(tests/common/vreport.sh); exits 1 on a failure."""
import argparse
import csv
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "postproc"))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from analytical import SourceColumn  # noqa: E402
from geoblock_h5 import Run, coordinate_order, script_main  # noqa: E402
from vreport import record  # noqa: E402


def load(path):
    return Run(os.path.dirname(path) or ".", os.path.basename(path))


def closed_form(run):
    """(SourceColumn, source name, section area, a) from the run's deck."""
    par = run.parameters()
    src = par["source"][0]
    mesh = par["mesh"][0]
    lo, up = np.asarray(mesh["lower"], float), np.asarray(mesh["upper"], float)
    mats = par["material"]
    mob = {m["permeability"] / m["viscosity"] for m in mats}
    if len(mob) != 1:
        raise ValueError("the column needs one permeability / viscosity in every region")
    p_b = [b["pressure"] for b in par["boundary"] if b["type"] == "pressure" and b["set"] == "zmax"]
    if len(p_b) != 1:
        raise ValueError("the column needs one pressure condition on zmax")
    region = [r for r in par["region"] if r["name"] == src["region"]][0]
    # a: the top of the region's cells (the region holds the cell centres
    # below its upper bound)
    zc = run.cell_centres()[:, 2]
    inside = zc <= region["upper"][2] + 1e-9
    a = run.coords[run.conn[inside]][:, :, 2].max() - lo[2]
    sc = SourceColumn(up[2] - lo[2], a, src["pressure"], p_b[0], src["index"], mob.pop())
    return sc, src["name"], (up[0] - lo[0]) * (up[1] - lo[1]), lo[2]


def errors(run):
    sc, name, area, z0 = closed_form(run)
    dp = abs(sc.p_w - sc.p_b)
    z = run.coords[run.conn][:, :, 2] - z0
    p = np.asarray(run.field("pressure"))
    exact = sc.cell_average(z.min(axis=1), z.max(axis=1))
    field = np.max(np.abs(p - exact)) / dp
    q = float(probe_rates(run, name)[-1])
    rate = abs(q - sc.rate() * area) / abs(sc.rate() * area)
    top = np.isclose(z.max(axis=1), sc.L)
    vz = np.asarray(run.field("darcy_velocity"))[:, 2]
    sections = [np.ptp(run.coords[run.conn[c]][:, 0]) * np.ptp(run.coords[run.conn[c]][:, 1])
                for c in np.nonzero(top)[0]]
    out = float(np.sum(vz[top] * np.asarray(sections)))
    balance = abs(out - q) / abs(q)
    frac = None
    fr = run.fractures(required=False)
    if fr is not None:
        zf = np.asarray(run.field("fractures/center"))[:, 2] - z0
        pf = np.asarray(run.field("fractures/pressure"))
        frac = np.max(np.abs(pf - sc.pressure(zf))) / dp
    return dict(field=field, rate=rate, balance=balance, fracture=frac, q=q, q_exact=sc.rate() * area,
                cells=len(p), m_a=sc.m * sc.a)


def steady(a):
    e = errors(load(a.run))
    case = f"{a.label}, {e['cells']} cells, m a = {e['m_a']:.3g}"
    ok = True
    rows = [("field", "cell pressures (largest error / |p_w - p_b|)", e["field"], a.tol),
            ("rate", f"source rate {e['q']:.6e} m3/s vs {e['q_exact']:.6e} (relative)", e["rate"], a.tol),
            ("balance", "outflow at the top vs the source's rate (relative)", e["balance"], a.balance)]
    if e["fracture"] is not None:
        rows.append(("fracture", "fracture pressures (largest error / |p_w - p_b|)", e["fracture"], a.tol))
    for _, what, err, tol in rows:
        good = record(case, what, err, tol)
        ok = ok and good
        print(f"{case}: {what} {err:.2e} (<= {tol:g}) {'ok' if good else 'FAIL'}")
    return 0 if ok else 1


def order(a):
    e1, e2 = errors(load(a.run_h)), errors(load(a.run_h2))
    ok = True
    for key, what in (("field", "cell pressures"), ("rate", "source rate")):
        q = math.log(e1[key] / e2[key], 2.0) if e1[key] > 0 and e2[key] > 0 else float("inf")
        good = record(f"{a.label}, {e1['cells']} -> {e2['cells']} cells", f"{what}: observed order", q, a.min_order,
                      order=q, passed=q >= a.min_order)
        ok = ok and good
        print(f"{a.label}: {what} error {e1[key]:.2e} -> {e2[key]:.2e}, order {q:.2f} (>= {a.min_order:g}) "
              f"{'ok' if good else 'FAIL'}")
    return 0 if ok else 1


def probe_rates(run, name):
    with open(os.path.join(run.dir, run.prefix + "_probes.csv")) as f:
        rows = list(csv.reader(f))
    col = rows[0].index(f"{name}:rate [m3/s]")
    return np.array([float(r[col]) for r in rows[1:]])


def same(a):
    ra, rb = load(a.run_a), load(a.run_b)
    if len(ra.steps) != len(rb.steps) or not ra.steps:
        print(f"{a.label}: FAIL steps {len(ra.steps)} vs {len(rb.steps)}")
        return 1
    oa, ob = coordinate_order(ra.cell_centres()), coordinate_order(rb.cell_centres())
    pa = np.array([np.asarray(ra.field("pressure", k))[oa] for k in range(len(ra.steps))])
    pb = np.array([np.asarray(rb.field("pressure", k))[ob] for k in range(len(rb.steps))])
    name = ra.parameters()["source"][0]["name"]
    qa, qb = probe_rates(ra, name), probe_rates(rb, name)
    ok = True
    for what, x, y in (("cell pressures, every step", pa, pb), ("source rate, every step", qa, qb)):
        d = float(np.max(np.abs(x - y)) / np.max(np.abs(x)))
        good = record(a.label, what + " (largest difference, relative)", d, a.tol)
        ok = ok and good
        print(f"{a.label}: {what}: {d:.2e} (<= {a.tol:g}) {'ok' if good else 'FAIL'}")
    return 0 if ok else 1


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="mode", required=True)
    s = sub.add_parser("steady")
    s.add_argument("run")
    s.add_argument("--tol", type=float, default=0.01)
    s.add_argument("--balance", type=float, default=1e-8)
    s.add_argument("--label", default="pressure-controlled source")
    o = sub.add_parser("order")
    o.add_argument("run_h")
    o.add_argument("run_h2")
    o.add_argument("--min-order", type=float, default=1.8)
    o.add_argument("--label", default="pressure-controlled source")
    m = sub.add_parser("same")
    m.add_argument("run_a")
    m.add_argument("run_b")
    m.add_argument("--tol", type=float, default=1e-8)
    m.add_argument("--label", default="pressure-controlled source")
    a = ap.parse_args()
    return {"steady": steady, "order": order, "same": same}[a.mode](a)


if __name__ == "__main__":
    script_main(main)
