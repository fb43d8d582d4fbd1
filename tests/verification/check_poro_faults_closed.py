"""Checks of physics = 'poromechanics_faults' against closed forms
(tests/verification/poro_faults_closed.sh, issue 33 deliverable 3).

usage:
  check_poro_faults_closed.py mandel FAULT_DIR BIOT_DIR PREFIX SIGMA [--tol TOL]
  check_poro_faults_closed.py gringarten DIR PREFIX --td-min TD --td-max TD [--tol TOL] [--spread-tol S]
  check_poro_faults_closed.py onset DIR PREFIX [--tol TOL]

mandel: Mandel's problem cut by a glued (stick), hydraulically transparent
(exchange 'open') fault (tests/decks/poro_faults_mandel.nml) against the
'biot' run of the same deck without the fault, in every cell, every node
and every step, within the fracture's storage effect (bound below), and
both against Mandel's closed form as tests/verification/check_mandel.py
compares it (the pressure at x = 0, a/2, 0.9a, TOL of p0, five times).

  The bound. What the fault adds to the uncut body is a fluid volume per
  element, V_e = A_e (g_N + a0 c_f p_f): its storage (the residual aperture
  a0 and the fluid compressibility c_f) and its compliance (the normal jump
  g_N that the stick rows' stabilization lets through, read from the
  output). The volume it takes in a step, dV_e, comes from the matrix
  beside it: taken from one cell alone (volume V_c, storage S_v = 1/M +
  b^2/K_v, the storage of Mandel's consolidation coefficient; in fact the
  two cells that share the element's faces give it) it moves that cell's
  pressure by dV_e / (V_c S_v). Summed over the steps without the
  diffusion that spreads it,
      B_p(n) = sum_{m <= n} max_e |dV_e^m| / (V_c S_v)
  bounds the pressure difference of step n in every cell. The displacement
  differs by the fault's jump, which the body around takes up: the largest
  difference of step n at any node is bounded by the largest jump
  |u_plus - u_minus| of the fault's split nodes at that step, plus the
  displacement that B_p(n) can drive through the coupling over the
  specimen's height, b B_p(n) b_half / K_v.

gringarten: a well producing at a constant rate from a highly conductive
vertical fracture through a slab (tests/decks/poro_faults_frac_well.nml;
half model: the fracture on y = 0 from x = 0, a symmetry plane, to its tip
x_f; the deck's &well rate is the half model's), the reservoir rigid (Biot
coefficient 0: the matrix is a diffusion problem of diffusivity
c = k M / mu). The well's pressure drop, in Gringarten, Ramey and
Raghavan's dimensionless form p_D = 2 pi k H dp / (q mu) (q the whole
well's rate, H the slab's height) at t_D = c t / x_f^2, against their
infinite-conductivity vertical fracture (see p_d_infinite_conductivity) at
every step with TD_MIN <= t_D <= TD_MAX: |p_D,h / p_D - 1| <= TOL; and
every element of the fracture at the well's pressure (the least drawdown
within SPREAD_TOL of the well's). The solution itself is checked first: its uniform-flux form against the
closed form (p_d_uniform_flux) to 1e-5, its early and late limits.

onset: a fault under a homogeneous stress in a permeable poroelastic block,
pressurized uniformly (tests/decks/poro_faults_onset.nml): the fault's
effective Coulomb function tau - tan(phi) (sigma_n - p_f) reaches zero when
the pressure reaches p_c = sigma_n - tau / tan(phi), at the time t_c that the
uniform pressurization p(t) gives. Checks: the fault's pressure and the
matrix's in every element and cell against p(t) at every step; no element
slips at a step ending before t_c; every element slips at the first step
ending at or after t_c, and that step is the one whose interval contains t_c.

Prints one line per check ('ok' or 'FAIL') and exits 1 on a failure."""
import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "postproc"))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "common"))
import csv  # noqa: E402
from math import factorial, log  # noqa: E402

import h5py  # noqa: E402
import numpy as np  # noqa: E402
from scipy.special import erf, exp1, iti0k0  # noqa: E402
from analytical import Mandel, PoroParams  # noqa: E402
from geoblock_h5 import Run, coordinate_order, read_parameters  # noqa: E402
from vreport import record  # noqa: E402


def verdict(good):
    return "ok" if good else "FAIL"


def fracture_fields(run, i, names):
    with h5py.File(run.steps[i], "r") as f:
        return [np.array(f["fractures/" + n]) for n in names]


def node_map(a, b):
    """For each node of run a, the node of run b at the same coordinates
    (a's split nodes map to b's one node)."""
    key = {tuple(x): j for j, x in enumerate(np.round(b.coords, 9))}
    return np.array([key[tuple(x)] for x in np.round(a.coords, 9)])


def split_pairs(run):
    """Pairs of nodes of run at the same coordinates (a fault's split nodes)."""
    seen = {}
    for j, x in enumerate(np.round(run.coords, 9)):
        seen.setdefault(tuple(x), []).append(j)
    return np.array([v[:2] for v in seen.values() if len(v) >= 2])


def hex_volumes(coords, conn):
    """Volumes of trilinear hexahedra (2 x 2 x 2 Gauss points: exact)."""
    ref = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                    [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], dtype=float)
    x = coords[conn]                                    # (cells, 8, 3)
    g = 1.0 / np.sqrt(3.0)
    vol = np.zeros(len(conn))
    for q in np.array(np.meshgrid([-g, g], [-g, g], [-g, g])).reshape(3, -1).T:
        dn = np.empty((8, 3))                           # d N_a / d xi_j at q
        for j in range(3):
            f = 1 + ref * q
            f[:, j] = ref[:, j]
            dn[:, j] = np.prod(f, axis=1) / 8.0
        vol += np.linalg.det(np.einsum("cai,aj->cij", x, dn))
    return vol


def mandel_closed(run, m, tol, label):
    """check_mandel.py's comparison: the pressure averaged over the cells at
    x ~ 0, a/2, 0.9a against the closed form at T = 0.01 ... 0.6."""
    xc = run.cell_centres()[:, 0]
    xs = np.unique(np.round(xc, 9))
    times = run.times()
    T = m.c * times / m.a ** 2
    ok, lines = True, []
    for target in (0.01, 0.05, 0.1, 0.3, 0.6):
        i = int(np.argmin(np.abs(T - target)))
        p = run.field("pressure", i)
        errs = []
        for x in (0.0, 0.5 * m.a, 0.9 * m.a):
            xn = xs[np.argmin(np.abs(xs - x))]
            sel = np.isclose(xc, xn)
            errs.append(abs(p[sel].mean() - float(m.pressure(xn, times[i]))) / m.p0)
        good = max(errs) <= tol
        ok = ok and good
        record(f"Mandel, {label}, T = {T[i]:.4f}", "pressure at x = 0, a/2, 0.9a (largest |p_h - p| / p0)",
               max(errs), tol, passed=good)
        lines.append(f"{label}: Mandel T = {T[i]:.4f}: |p_h - p| / p0 at x = 0, a/2, 0.9a: "
                     + ", ".join(f"{e:.2e}" for e in errs) + f" (tol {tol:g}) {verdict(good)}")
    return ok, lines


def mandel(args):
    a, b = Run(args.fault_dir, args.prefix), Run(args.biot_dir, args.prefix)
    par = a.parameters()
    pp = PoroParams.from_namelist(par["material"][0])
    ff = par["fracture_flow"][0]
    a0, cf = float(ff["residual_aperture"]), float(ff["compressibility"])
    half_w, half_h = np.ptp(a.coords[:, 0]), np.ptp(a.coords[:, 1])
    m = Mandel.from_traction(pp, half_w, half_h, args.sigma)
    ok = True
    case = f"Mandel cut by a glued transparent fault, {len(a.conn)} cells"
    if len(a.steps) != len(b.steps) or np.max(np.abs(a.times() - b.times())) > 1e-12 * a.times()[-1]:
        print(f"the runs' steps differ: {len(a.steps)} and {len(b.steps)} FAIL")
        return False
    ca, cb = coordinate_order(a.cell_centres()), coordinate_order(b.cell_centres())
    nb = node_map(a, b)
    pairs = split_pairs(a)
    vol = np.min(hex_volumes(a.coords, a.conn))
    s_v = pp.S_v
    acc, prev = 0.0, None
    dp_w = du_w = r_p = r_u = 0.0
    store_w = comp_w = 0.0
    stick, tn_max = True, -np.inf
    for i in range(len(b.steps)):
        op, pf, area, st, tn = fracture_fields(a, i, ("opening", "pressure", "area", "status", "normal_traction"))
        stick = stick and bool(np.all(st == 0))
        tn_max = max(tn_max, float(tn.max()))
        v = area * (op + a0 * cf * pf)
        if prev is not None:
            acc += np.max(np.abs(v - prev))
            comp_w = max(comp_w, np.max(np.abs(area * (op - prev_op))))
            store_w = max(store_w, np.max(np.abs(area * a0 * cf * (pf - prev_pf))))
        prev, prev_op, prev_pf = v, op, pf
        bound_p = acc / (vol * s_v)
        dp = np.max(np.abs(a.field("pressure", i)[ca] - b.field("pressure", i)[cb]))
        ua = a.field("displacement", i)
        du = np.max(np.abs(ua - b.field("displacement", i)[nb]))
        jump = np.max(np.abs(ua[pairs[:, 1]] - ua[pairs[:, 0]]))
        bound_u = jump + pp.b * bound_p * half_h / pp.K_v
        tiny = 1e-12 * m.p0
        r_p = max(r_p, dp / max(bound_p, tiny))
        r_u = max(r_u, du / max(bound_u, 1e-12 * np.max(np.abs(ua))))
        dp_w, du_w = max(dp_w, dp), max(du_w, du)
    good = r_p <= 1.0
    ok = ok and good
    record(case, "cell pressure against biot's uncut run, every step (/ the storage bound B_p)", r_p, 1.0, passed=good)
    print(f"glued transparent fault vs biot's uncut Mandel: largest cell pressure difference {dp_w:.3e} Pa "
          f"({dp_w / m.p0:.2e} p0); against the fault's storage bound B_p, largest ratio {r_p:.3f} (tol 1); "
          f"B_p at the end {bound_p / m.p0:.2e} p0 (largest step volumes: compliance {comp_w:.2e} m3, "
          f"storage a0 c_f {store_w:.2e} m3) {verdict(good)}")
    good = r_u <= 1.0
    ok = ok and good
    record(case, "node displacement against biot's uncut run, every step (/ the jump bound)", r_u, 1.0, passed=good)
    print(f"glued transparent fault vs biot's uncut Mandel: largest node displacement difference {du_w:.3e} m "
          f"({du_w / np.max(np.abs(b.field('displacement', -1))):.2e} of the largest displacement); against "
          f"the fault's jump + b B_p b_half / K_v, largest ratio {r_u:.3f} (tol 1) {verdict(good)}")
    good = stick and tn_max < 0.0
    ok = ok and good
    print(f"the fault sticks at every step, closed: largest normal traction {tn_max:.4e} Pa {verdict(good)}")
    for run, label in ((a, "with the fault"), (b, "biot, uncut")):
        good, lines = mandel_closed(run, m, args.tol, label)
        ok = ok and good
        print("\n".join(lines))
    return ok


# -- Gringarten, Ramey and Raghavan (1974): "Unsteady-state pressure
# distributions created by a well with a single infinite-conductivity
# vertical fracture", SPE Journal 14 (4), 347-360. Dimensionless
# variables: x_D = x / x_f, t_D = c t / x_f^2, p_D = 2 pi k H dp / (q mu).

def p_d_uniform_flux(td, xd=0.0):
    """Their uniform-flux fracture (eq. 12) at x_D along it:
    p_D = sqrt(pi t_D)/2 [erf((1 + x_D)/(2 sqrt t_D)) + erf((1 - x_D)/(2 sqrt t_D))]
          - (1 + x_D)/4 Ei(-(1 + x_D)^2/(4 t_D)) - (1 - x_D)/4 Ei(-(1 - x_D)^2/(4 t_D)),
    with -Ei(-u) = E1(u). At x_D = 0.732 their approximation of the
    infinite-conductivity fracture."""
    td = np.asarray(td, dtype=float)
    r = 2.0 * np.sqrt(td)
    return (0.5 * np.sqrt(np.pi * td) * (erf((1 + xd) / r) + erf((1 - xd) / r))
            + 0.25 * (1 + xd) * exp1((1 + xd) ** 2 / (4 * td)) + 0.25 * (1 - xd) * exp1((1 - xd) ** 2 / (4 * td)))


def _stehfest(n=12):
    """Stehfest's weights V_i (Comm. ACM 13 (1970) 47)."""
    h = n // 2
    v = np.zeros(n)
    for i in range(1, n + 1):
        v[i - 1] = (-1) ** (i + h) * sum(k ** h * factorial(2 * k) / (factorial(h - k) * factorial(k) * factorial(k - 1)
                                         * factorial(i - k) * factorial(2 * k - i))
                                         for k in range((i + 1) // 2, min(i, h) + 1))
    return v


_V = _stehfest()


def _invert(fbar, td):
    a = log(2.0) / td
    return a * sum(v * fbar((i + 1) * a) for i, v in enumerate(_V))


def _k0_segments(x, edges, s):
    """int over each segment [e_j, e_j+1] of K0(sqrt(s) |x_i - x'|) dx'."""
    r = np.sqrt(s)

    def ik(u):                                          # int_0^u K0 (a ufunc)
        return iti0k0(u)[1]
    a = edges[None, :-1] - x[:, None]
    b = edges[None, 1:] - x[:, None]
    return (np.sign(b) * ik(r * np.abs(b)) - np.sign(a) * ik(r * np.abs(a))) / r


def _pbar_infinite_conductivity(s, n=60):
    """Laplace transform of the well's p_D: the fracture -1 < x_D < 1 as n
    segments per wing (finer at the tip) of unknown flux density f_j, the
    pressure of a continuous line source of unit rate being (1/2) E1(r^2/(4 t_D)),
    K0(r sqrt s) / s in Laplace space: the same pressure p_w at every segment's
    centre, the fluxes summing to the rate (1/s)."""
    e = np.sin(np.linspace(0.0, 0.5 * np.pi, n + 1))
    xc, w = 0.5 * (e[1:] + e[:-1]), np.diff(e)
    a = np.zeros((n + 1, n + 1))
    a[:n, :n] = _k0_segments(xc, e, s) + _k0_segments(-xc, e, s)   # both wings
    a[:n, n] = -1.0
    a[n, :n] = 2.0 * w
    rhs = np.zeros(n + 1)
    rhs[n] = 1.0 / s
    return np.linalg.solve(a, rhs)[n]


def p_d_infinite_conductivity(td):
    """Their infinite-conductivity fracture, the well's p_D(t_D): the
    uniform pressure along the fracture and the flux it draws solved in
    Laplace space (_pbar_infinite_conductivity), inverted by Stehfest's
    algorithm (12 terms)."""
    return np.array([_invert(_pbar_infinite_conductivity, t) for t in np.atleast_1d(td)])


def solution_self_check():
    """The Laplace solution and the inversion against the uniform-flux closed
    form (the same kernel with a uniform flux) and the limits: linear flow
    sqrt(pi t_D) early, pseudo-radial 0.5 (ln t_D + 2.2) late."""
    def uf(s, xd):
        return 0.5 / s * _k0_segments(np.array([xd]), np.array([-1.0, 1.0]), s)[0, 0]
    tds = [1e-3, 1e-2, 0.1, 1.0, 10.0]
    e_uf = max(abs(_invert(lambda s: uf(s, 0.732), t) / p_d_uniform_flux(t, 0.732) - 1) for t in tds)
    early = abs(p_d_infinite_conductivity(1e-4)[0] / np.sqrt(np.pi * 1e-4) - 1)
    late = abs(p_d_infinite_conductivity(1e3)[0] / (0.5 * (np.log(1e3) + 2.2)) - 1)
    good = e_uf <= 1e-5 and early <= 0.01 and late <= 0.002
    print(f"infinite-conductivity solution (Laplace, Stehfest): its uniform-flux form against the closed form "
          f"{e_uf:.1e} (tol 1e-5); p_D / sqrt(pi t_D) - 1 at t_D = 1e-4: {early:.1e} (tol 0.01), "
          f"p_D / (0.5 (ln t_D + 2.2)) - 1 at t_D = 1e3: {late:.1e} (tol 0.002) {verdict(good)}")
    return good


def gringarten(args):
    ok = solution_self_check()
    run = args.dir
    par = read_parameters(os.path.join(run, args.prefix + "_parameters.nml"))
    mat, mesh = par["material"][0], par["mesh"][0]
    k, mu, m_b = float(mat["permeability"]), float(mat["viscosity"]), float(mat["biot_modulus"])
    c = k * m_b / mu
    h = float(mesh["upper"][2]) - float(mesh["lower"][2])
    xf = float(par["fault"][0]["upper"][0])
    well = par["well"][0]
    q = 2.0 * abs(float(well["rate"]))                  # the half model's rate, doubled
    with open(os.path.join(run, args.prefix + "_probes.csv")) as f:
        rows = list(csv.DictReader(f))
    t = np.array([float(r["time [s]"]) for r in rows])
    dp = -np.array([float(r[well["name"] + ":pressure [Pa]"]) for r in rows])
    td = c * t / xf ** 2
    sel = (td >= args.td_min * (1 - 1e-9)) & (td <= args.td_max * (1 + 1e-9))
    pd_h = 2.0 * np.pi * k * h * dp[sel] / (q * mu)
    pd = p_d_infinite_conductivity(td[sel])
    err = np.abs(pd_h / pd - 1.0)
    worst = int(np.argmax(err))
    good = sel.sum() >= 10 and err.max() <= args.tol
    ok = ok and good
    f_cd = float(par["fracture_flow"][0]["residual_aperture"]) ** 3 / (12.0 * k * xf)
    case = f"well in an infinite-conductivity fracture (F_CD {f_cd:.2g}), rigid reservoir"
    record(case, f"well pressure p_D against Gringarten et al. (1974), {sel.sum()} steps, t_D {td[sel][0]:.2g} - "
           f"{td[sel][-1]:.3g} (largest relative error)", float(err.max()), args.tol, passed=good)
    print(f"well pressure against the infinite-conductivity fracture at {sel.sum()} steps, t_D = {td[sel][0]:.3g} to "
          f"{td[sel][-1]:.3g}: largest |p_D,h / p_D - 1| {err.max():.2e} at t_D = {td[sel][worst]:.3g} "
          f"(p_D,h {pd_h[worst]:.4f}, p_D {pd[worst]:.4f}) (tol {args.tol:g}) {verdict(good)}")
    # infinite conductivity: the fracture's elements (the tip's too) at the
    # well's pressure; the probes give the fault's largest pressure, the
    # least drawdown (production from zero)
    spread = np.abs(np.array([float(r["frac:max_pressure [Pa]"]) for r in rows])[sel] + dp[sel]) / dp[sel]
    good = spread.max() <= args.spread_tol
    ok = ok and good
    record(case, "pressure along the fracture: least drawdown against the well's, every checked step (relative)",
           float(spread.max()), args.spread_tol, passed=good)
    print(f"pressure along the fracture: the least drawdown of an element within {spread.max():.2e} of the well's "
          f"(tol {args.spread_tol:g}) {verdict(good)}")
    # the flow regimes the checked range crosses (figures of the run)
    lin = pd_h[0] / np.sqrt(np.pi * td[sel][0])
    slope_early = np.log(pd_h[1] / pd_h[0]) / np.log(td[sel][1] / td[sel][0])
    slope_late = (pd_h[-1] - pd_h[-2]) / np.log(td[sel][-1] / td[sel][-2])
    print(f"flow regimes: at t_D = {td[sel][0]:.3g} p_D,h / sqrt(pi t_D) = {lin:.3f} and d ln p_D / d ln t_D = "
          f"{slope_early:.3f} (linear flow: 1, 0.5); at t_D = {td[sel][-1]:.3g} d p_D / d ln t_D = {slope_late:.3f} "
          f"(pseudo-radial flow: 0.5)")
    return ok


def onset(args):
    run = Run(args.dir, args.prefix)
    par = run.parameters()
    pp = PoroParams.from_namelist(par["material"][0])
    sig = np.zeros(3)                                   # the homogeneous total stress (tension > 0)
    for bc in par["boundary"]:
        if bc.get("type") == "traction":
            t = np.asarray(bc["traction"], dtype=float)
            k = int(np.argmax(np.abs(t)))
            sig[k] = t[k]
    fault = par["fault"][0]
    dip = np.radians(float(fault["dip"]))
    n = np.array([-np.sin(dip), 0.0, np.cos(dip)])       # normal z, dipping along x
    tv = sig * n
    s_n = -float(tv @ n)                                # compression positive
    tau = float(np.linalg.norm(tv - (tv @ n) * n))
    coh, mu_f = float(fault.get("cohesion", 0.0)), np.tan(np.radians(float(fault["friction_angle"])))
    p_c = s_n - (tau - coh) / mu_f
    # undrained start: p_u = -B tr(sigma)/3; then, the total stress fixed, the
    # pressure rises uniformly: Q dt = (V (1/M + b^2/K) + A a0 c_f) dp
    p_u = -pp.B * sig.sum() / 3.0
    lo, up = np.array(par["mesh"][0]["lower"], float), np.array(par["mesh"][0]["upper"], float)
    vol = float(np.prod(up - lo))
    ff = par["fracture_flow"][0]
    area = fracture_fields(run, 0, ("area",))[0].sum()
    a0_cf = float(ff["residual_aperture"]) * float(ff["compressibility"])
    store = vol * (pp.inv_M + pp.b ** 2 / pp.K_dr) + area * a0_cf
    q = float(par["well"][0]["rate"])
    t_c = (p_c - p_u) * store / q
    times = run.times()
    dt = float(np.min(np.diff(times)))
    rise = q * dt / store                               # the pressure's rise in a step
    ok = True
    print(f"fault: sigma_n {s_n:.6e} Pa, tau {tau:.6e} Pa, cohesion {coh:.3g} Pa, tan(phi) {mu_f:.4f}: "
          f"p_c = {p_c:.6e} Pa; p_u = {p_u:.6e} Pa, dp/dt = {q / store:.6e} Pa/s: t_c = {t_c:.4f} s")
    first = None
    e_p = e_c = 0.0
    early = []
    for i, t in enumerate(times):
        st, pf, cff = fracture_fields(run, i, ("status", "pressure", "cff"))
        if first is None:
            p_ex = p_u + q * t / store
            e_p = max(e_p, np.max(np.abs(run.field("pressure", i) - p_ex)), np.max(np.abs(pf - p_ex)))
            if np.all(st == 0):
                e_c = max(e_c, np.max(np.abs(cff - (tau - coh - mu_f * (s_n - p_ex)))))
        if np.any(st != 0):
            if t < t_c:
                early.append(i)
            if first is None:
                first = i
                n_slip, n_el = int(np.sum(st == 1)), len(st)
    case = f"injection into a fault until it slips, {len(run.conn)} cells, {len(st)} elements"
    good = e_p <= args.tol * rise
    ok = ok and good
    record(case, "pressure of every cell and element against the uniform rise, every step to the onset "
           "(/ a step's rise)", e_p / rise, args.tol, passed=good)
    print(f"pressure of every cell and fault element against p_u + Q t / (V S + A a0 c_f), steps 0 to the onset: "
          f"largest error {e_p:.3e} Pa = {e_p / rise:.2e} of a step's rise {rise:.4e} Pa (tol {args.tol:g}) "
          f"{verdict(good)}")
    good = e_c <= args.tol * mu_f * rise
    ok = ok and good
    record(case, "Coulomb function of every element against tau - c - tan(phi) (sigma_n - p), every stick step "
           "(/ tan(phi) a step's rise)", e_c / (mu_f * rise), args.tol, passed=good)
    print(f"Coulomb function (output cff) of every element against tau - c - tan(phi) (sigma_n - p(t)), stick steps: "
          f"largest error {e_c:.3e} Pa = {e_c / (mu_f * rise):.2e} of tan(phi) x a step's rise (tol {args.tol:g}) "
          f"{verdict(good)}")
    if first is None:
        print(f"no element slips up to t = {times[-1]:.4g} s (t_c = {t_c:.4f} s) FAIL")
        return False
    good = not early and times[first - 1] < t_c <= times[first] and n_slip == n_el
    ok = ok and good
    record(case, "onset of slip: the step after t_c's (steps; 0 when it contains t_c)",
           first - int(np.searchsorted(times, t_c)), 0, passed=good)
    print(f"onset: no element slips at a step ending before t_c ({len(early)} found); the first slip at step {first} "
          f"(t = {times[first - 1]:.4g} to {times[first]:.4g} s, t_c = {t_c:.4f} s), {n_slip} of {n_el} elements "
          f"slipping {verdict(good)}")
    return ok


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="what", required=True)
    p = sub.add_parser("mandel")
    p.add_argument("fault_dir")
    p.add_argument("biot_dir")
    p.add_argument("prefix")
    p.add_argument("sigma", type=float, help="plate stress [Pa], compression positive")
    p.add_argument("--tol", type=float, default=0.02)
    p = sub.add_parser("gringarten")
    p.add_argument("dir")
    p.add_argument("prefix")
    p.add_argument("--td-min", type=float, required=True)
    p.add_argument("--td-max", type=float, required=True)
    p.add_argument("--tol", type=float, default=0.03)
    p.add_argument("--spread-tol", type=float, default=0.01)
    p = sub.add_parser("onset")
    p.add_argument("dir")
    p.add_argument("prefix")
    p.add_argument("--tol", type=float, default=0.01)
    args = ap.parse_args()
    ok = {"mandel": mandel, "gringarten": gringarten, "onset": onset}[args.what](args)
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
