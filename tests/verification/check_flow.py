#!/usr/bin/env python3
"""Checks of physics = 'fracture_flow' runs (tests/verification/fracture_flow.sh).

    check_flow.py mass RUN Q TOL      every step: change of fracture volume plus
                                      compressibility storage = Q dt (relative to Q dt)
    check_flow.py sneddon RUN Q LZ TOL  mean pressure at the last step against
                                      E (Q/LZ) t / (2 pi (1 - nu^2) b^2)
    check_flow.py penny RUN TOL       mean pressure of one circular fracture (&fault radius)
                                      at every step against Sneddon's penny crack,
                                      p = 3 E V / (16 (1 - nu^2) a_eq^3): V the volume injected
                                      so far (the wells' rates of the probes CSV over the steps),
                                      a_eq = sqrt(A / pi) of the staircase disc's area A; a disc
                                      whose centre lies on box faces (symmetry planes) is a half
                                      or quarter model, and V and A count the full disc; the
                                      fracture's fluid volume must equal V (1e-10)
    check_flow.py same RUN1 RUN2 TOL  pressure and opening of two runs (by element centre)
    check_flow.py cubic RUN A0 MU DP L TOL  steady flow between two prescribed pressures: the
                                      flux of every element between them against
                                      a0^3 dp / (12 mu L), the pressure linear between them
    check_flow.py onset RUN TOL       the pressure at which the fault 'fault' starts to slip
                                      (probes CSV: between the last all-stick step and the
                                      first slipping one) against sigma_n - tau / tan(phi)
                                      for the homogeneous stress of the deck's tractions; the
                                      fault 'far' keeps its initial pressure (to 1e-10), no slip, no fluid (1e-15 m3)
    check_flow.py split RUN W H NL NR TOL  one well along a segment crossing fractures whose
                                      end elements are held (&fracture_pressure) and that are
                                      1-D chains of elements h apart and w wide, the well NL
                                      edges from one end and NR from the other: at the last
                                      step each connection's rate against
                                      (p_w - p_end) / (1/J + 1/G), G = a0^3 w / (12 mu h) (1/NL + 1/NR),
                                      J the deck's index or Peaceman's
                                      2 pi a0^3 / (12 mu ln(0.14 sqrt(h^2 + w^2) / r_w)),
                                      p_w from sum q = Q; the rates sum to Q (1e-12) and each is
                                      J (p_w - p_c) with the CSV's pressures (1e-10)
RUN is the output directory plus prefix. Prints one line; exit 1 on a failure.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "postproc"))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from geoblock_h5 import Run  # noqa: E402
from vreport import record  # noqa: E402


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
    return record(f"injection into a fracture, {len(times) - 1} steps", "fluid volume against Q dt (largest relative "
                  "error)", worst, tol)


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
    flux = np.asarray(run.field("fractures/flux", -1))
    # the well feeds the centre: through the crack's half-width at the well
    # the flow per unit width is at most Q / (2 LZ), and it vanishes at the tips
    fmax = float(flux.max())
    print(f"sneddon: t = {t:g} s, mean p {mean:.6e} Pa, exact {exact:.6e} Pa, error {err:.3e}, spread {spread:.2e}, "
          f"largest flux {fmax:.3e} m2/s (Q / (2 LZ) = {q / (2 * lz):.3e})")
    good = err <= tol and np.all(np.isfinite(flux)) and 0.0 < fmax <= q / (2 * lz) * (1 + 1e-12)
    record(f"plane strain fracture, {len(p)} elements, t = {t:g} s", "mean pressure against Sneddon's volume "
           "(relative error)", err, tol, passed=good)
    return good


def penny(path, tol):
    import csv
    run = load(path)
    par = run.parameters()
    e, nu = float(par["material"][0]["young"]), float(par["material"][0]["poisson"])
    faults = par["fault"]
    if len(faults) != 1 or "radius" not in faults[0]:
        print("penny: the run must have one &fault, with a radius (a circular fracture)")
        return False
    fault, mesh = faults[0], par["mesh"][0]
    normal = "xyz".index(fault["normal_axis"])
    lower = np.asarray(mesh["lower"], dtype=float)
    upper = np.asarray(mesh["upper"], dtype=float)
    centre = np.asarray(fault["centre"], dtype=float)
    tol_box = 1e-12 * np.abs(upper - lower).max()
    # each box face through the disc's centre is a symmetry plane that halves the model
    cut = [i for i in range(3) if i != normal and min(abs(centre[i] - lower[i]), abs(centre[i] - upper[i])) <= tol_box]
    parts = 2 ** len(cut)
    with open(path + "_probes.csv") as fh:
        rows = list(csv.DictReader(fh))
    t = np.array([float(r["time [s]"]) for r in rows])
    rates = [c for c in rows[0] if c.endswith(":rate [m3/s]")]
    q = np.array([sum(float(r[c]) for c in rates) for r in rows])
    # injected volume of the full disc up to each row (implicit Euler: the step's rate over the step)
    injected = parts * np.concatenate([[0.0], np.cumsum(q[1:] * np.diff(t))])
    held = parts * np.array([float(r[fault["name"] + ":fluid_volume [m3]"]) for r in rows])
    _, _, _, _, area = fields(run, -1)
    a_eq = np.sqrt(parts * np.sum(area) / np.pi)
    compliance = 16.0 * (1.0 - nu**2) * a_eq**3 / (3.0 * e)    # Sneddon: V = compliance * p
    errs = []
    for k, tk in enumerate(run.times()):
        row = np.flatnonzero(np.abs(t - tk) <= 1e-12 * max(abs(tk), 1.0))
        if tk <= 0.0 or len(row) != 1:
            continue
        _, _, p, _, area = fields(run, k)
        exact = injected[row[0]] / compliance
        mean = np.sum(area * p) / np.sum(area)
        errs.append((abs(mean - exact) / exact, tk, mean, exact, (p.max() - p.min()) / exact))
    if not errs:
        print("penny: no output step after t = 0 with a row of the probes file")
        return False
    err, tk, mean, exact, spread = errs[-1]
    worst = max(x[0] for x in errs)
    balance = float(np.abs(held - injected).max() / injected[-1])
    print(f"penny: 1/{parts} model, {len(p)} elements, a_eq {a_eq:.5f} m (radius {float(fault['radius']):g} m); "
          f"t = {tk:g} s: V = {injected[-1]:.6e} m3, mean p {mean:.6e} Pa, exact {exact:.6e} Pa, error {err:.3e}, "
          f"spread {spread:.2e}; largest error of the {len(errs)} steps {worst:.3e}; "
          f"fluid volume - injected {balance:.1e}")
    record(f"penny-shaped fracture, {len(p)} elements", "mean pressure against Sneddon's penny crack (largest "
           "relative error of the steps)", worst, tol, passed=worst <= tol and balance <= 1e-10)
    return worst <= tol and balance <= 1e-10


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


def cubic(path, a0, mu, dp, length, tol):
    run = load(path)
    centre, _, p, aperture, _ = fields(run, -1)
    flux = np.asarray(run.field("fractures/flux", -1))
    y = centre[:, 1]
    y0, y1 = y.min(), y.max()                           # the prescribed columns
    inner = (y > y0 + 1e-9) & (y < y1 - 1e-9)
    exact = a0**3 * dp / (12.0 * mu * length)
    ef = float(np.abs(flux[inner] / exact - 1.0).max())
    p_lin = p[y == y0][0] - dp * (y - y0) / length
    ep = float(np.abs(p - p_lin).max() / dp)
    ea = float(np.abs(aperture / a0 - 1.0).max())
    print(f"cubic: {inner.sum()} elements between the prescribed columns, flux {flux[inner].mean():.6e} m2/s against "
          f"a0^3 dp / (12 mu L) = {exact:.6e}: largest error {ef:.2e}; pressure linear to {ep:.2e}; aperture a0 to {ea:.1e}")
    record(f"closed fracture between two pressures, {inner.sum()} elements", "flux against the cubic law "
           "(largest relative error)", ef, tol, passed=ef <= tol and ep <= tol and ea == 0.0)
    return ef <= tol and ep <= tol and ea == 0.0


def onset(path, tol):
    import csv
    run = load(path)
    par = run.parameters()
    sig = np.zeros(3)
    for b in par["boundary"]:
        if b.get("type") == "traction":
            t = np.asarray(b["traction"], dtype=float)
            k = int(np.argmax(np.abs(t)))
            sig[k] = t[k]                               # the max faces carry sigma_kk
    fault = [f for f in par["fault"] if f["name"] == "fault"][0]
    dip = np.radians(float(fault["dip"]))
    n = np.array([-np.sin(dip), 0.0, np.cos(dip)])      # normal z, dipping along x
    tv = sig * n
    sn = -float(tv @ n)                                 # compression positive
    tau = float(np.linalg.norm(tv - (tv @ n) * n))
    exact = sn - tau / np.tan(np.radians(float(fault["friction_angle"])))
    with open(path + "_probes.csv") as fh:
        rows = list(csv.DictReader(fh))
    area = [float(r["fault:slip_area [m2]"]) for r in rows]
    pres = [float(r["fault:max_pressure [Pa]"]) for r in rows]
    first = next((i for i, a in enumerate(area) if a > 0.0), None)
    if first is None or first == 0:
        print(f"onset: no onset of slip (exact {exact:.4e} Pa)")
        return False
    lo, hi = pres[first - 1], pres[first]
    mid = 0.5 * (lo + hi)
    err = abs(mid - exact) / exact
    far_p = max(abs(float(r["far:max_pressure [Pa]"])) for r in rows)
    far_v = max(abs(float(r["far:fluid_volume [m3]"])) for r in rows)
    far_s = max(float(r["far:slip_area [m2]"]) for r in rows)
    print(f"onset: sigma_n {sn:.4e} Pa, tau {tau:.4e} Pa, exact {exact:.4e} Pa; slip starts between "
          f"{lo:.4e} and {hi:.4e} Pa (step {first}), error of the midpoint {err:.2e}; far fracture: "
          f"largest pressure {far_p:.1e} Pa, fluid volume {far_v:.1e} m3, slip area {far_s:.1e} m2")
    # the far fracture: round-off only (its stick rows let through jumps of 1e-19 m)
    good = lo < exact <= hi and err <= tol and far_p <= 1e-10 * exact and far_v <= 1e-15 and far_s == 0.0
    record("fault fed by a well, onset of slip", "pressure at the onset against the effective Coulomb limit "
           "(midpoint of the bracket, relative error)", err, tol, passed=good)
    return good


def split(path, w, h, nl, nr, tol):
    import csv
    run = load(path)
    par = run.parameters()
    ff = par["fracture_flow"][0]
    a0, mu = float(ff["residual_aperture"]), float(ff["viscosity"])
    well = par["well"][0]
    name, q = well["name"], float(well["rate"])
    p_end = {g["fault"]: float(g["value"]) for g in par["fracture_pressure"]}
    faults = sorted(p_end)
    if "index" in well:
        j = float(well["index"])
        how = "the deck's index"
    else:
        r_e = 0.14 * np.hypot(h, w)
        j = 2.0 * np.pi * a0**3 / (12.0 * mu * np.log(r_e / float(well["radius"])))
        how = f"Peaceman's (r_e {r_e:.4g} m)"
    g = a0**3 * w / (12.0 * mu * h) * (1.0 / nl + 1.0 / nr)
    c = 1.0 / (1.0 / j + 1.0 / g)
    pw = (q + sum(c * p_end[f] for f in faults)) / (len(faults) * c)
    with open(path + "_probes.csv") as fh:
        last = list(csv.DictReader(fh))[-1]
    rate = {f: float(last[f"{name}@{f}:rate [m3/s]"]) for f in faults}
    pres = {f: float(last[f"{name}@{f}:pressure [Pa]"]) for f in faults}
    pw_csv = float(last[f"{name}:pressure [Pa]"])
    e_rate = max(abs(rate[f] / (c * (pw - p_end[f])) - 1.0) for f in faults)
    e_sum = abs(sum(rate.values()) - q) / q
    e_j = max(abs(rate[f] - j * (pw_csv - pres[f])) / abs(rate[f]) for f in faults)
    shown = ", ".join(f"{f} {rate[f]:.6e} (exact {c * (pw - p_end[f]):.6e})" for f in faults)
    print(f"split: J {j:.4e} m3/(Pa s) ({how}), rates {shown} m3/s: largest error {e_rate:.2e}; "
          f"sum against Q {e_sum:.1e}; q = J (p_w - p) to {e_j:.1e}")
    record(f"segment well across {len(faults)} fractures ({how})", "each fracture's rate against the conductances "
           "(largest relative error)", e_rate, tol, passed=e_rate <= tol and e_sum <= 1e-12 and e_j <= 1e-10)
    return e_rate <= tol and e_sum <= 1e-12 and e_j <= 1e-10


if __name__ == "__main__":
    if len(sys.argv) < 2 or sys.argv[1] in ("-h", "--help"):
        print(__doc__)
        sys.exit(0)
    cmd, args = sys.argv[1], sys.argv[2:]
    if cmd == "mass":
        ok = mass(args[0], float(args[1]), float(args[2]))
    elif cmd == "sneddon":
        ok = sneddon(args[0], float(args[1]), float(args[2]), float(args[3]))
    elif cmd == "penny":
        ok = penny(args[0], float(args[1]))
    elif cmd == "cubic":
        ok = cubic(args[0], *[float(v) for v in args[1:6]])
    elif cmd == "onset":
        ok = onset(args[0], float(args[1]))
    elif cmd == "split":
        ok = split(args[0], *[float(v) for v in args[1:5]], float(args[5]))
    elif cmd == "same":
        ok = same(args[0], args[1], float(args[2]))
    else:
        sys.exit(f"check_flow.py: unknown check '{cmd}'")
    sys.exit(0 if ok else 1)
