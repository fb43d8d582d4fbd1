"""Checks of geoblock's geostatic start (tests/verification/geostatic.sh).

usage:
  check_geostatic.py column RUN
      the two-layer column (meshes/two_layers.msh: 'rock' below z = 0.6,
      'cap' above, top z = 1) at rest: step 0's balancing displacement (the
      log) and the displacement at every step below 1e-9 of rho g H^2 / E, and the stress at every cell centre
      is the lithostatic effective stress (below 1e-9 of the largest);
      the log's imbalance below 1e-10
  check_geostatic.py superposition RUN DRY
      RUN (in situ, loaded) against DRY (the same load, no gravity): the
      displacements equal (1e-7 of the largest), the stresses differ by the
      in-situ stress (1e-7 of the largest of DRY's)
  check_geostatic.py flat_fault RUN
      the column's horizontal fault at z = 0.6: normal traction sigma'_v(0.6)
      and no shear on every element (1e-9), no slip
  check_geostatic.py dip_fault RUN S RHO K0 TOP
      a dry box under surface stress S, density RHO, ratio K0, top z = TOP:
      at step 0 every element's traction is the in-situ traction at its
      centre within a quarter of rho g dz (dz: the element's vertical
      extent); at the last step the slip is below 1e-12 m
  check_geostatic.py biot_column RUN
      the column with flow at rest: zero displacement, pressure change and
      the hydrostatic total pressure, the lithostatic total stress (1e-9)
  check_geostatic.py biot_superposition RUN DRY
      the loaded column with flow against the dry run, every step (1e-7)
RUN and DRY are output directory/prefix paths (build/test-out/x/NAME).
The densities, K0s, Poisson's ratios, water table, gravity and surface
stress are read from the run's resolved deck. Prints one line per check;
exits 1 on a failure."""
import os
import re
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "postproc"))
import numpy as np  # noqa: E402
from geoblock_h5 import Run, script_main  # noqa: E402


def open_run(path):
    return Run(os.path.dirname(path), os.path.basename(path))


def in_situ(par):
    """(sigma_v(z, rho of the layers above), p0(z), k0 per region) of a run's deck."""
    geo = par["geostatic"][0]
    g = float(geo.get("gravity", 9.81))
    rho_f = float(geo.get("fluid_density", 1000.0))
    zw = geo.get("water_table")
    surface = float(geo.get("surface_stress", 0.0))
    mats = {m["region"]: m for m in par["material"]}
    k0 = {}
    for name, m in mats.items():
        k0[name] = float(m["k0"]) if "k0" in m else float(m["poisson"]) / (1.0 - float(m["poisson"]))

    def p0(z):
        return 0.0 if zw is None else rho_f * g * np.maximum(float(zw) - z, 0.0)
    return g, surface, p0, k0, {n: float(m["density"]) for n, m in mats.items()}


def horizontal_ratios(par, region, k0):
    """The horizontal effective stress / sigma'_v of a region as the (xx, yy,
    xy) ratios: K0 in every direction, or k0_max along the azimuth
    sh_max_azimuth (degrees clockwise from +y) and K0 across it."""
    m = {m["region"]: m for m in par["material"]}[region]
    kmax = float(m.get("k0_max", k0[region]))
    az = np.radians(float(par["geostatic"][0].get("sh_max_azimuth", 0.0)))
    d = np.array([np.sin(az), np.cos(az)])
    e = np.array([d[1], -d[0]])
    t = kmax * np.outer(d, d) + k0[region] * np.outer(e, e)
    return t[0, 0], t[1, 1], t[0, 1]


def column_state(par, z):
    """Effective in-situ stress (n, 6) of the two-layer column at heights z."""
    g, surface, p0, k0, rho = in_situ(par)
    sv = -(surface + g * (rho["cap"] * (1.0 - np.maximum(z, 0.6)) + rho["rock"] * np.maximum(0.6 - z, 0.0)))
    sve = sv + p0(z)
    rock = z < 0.6
    s = np.zeros((len(z), 6))
    for region, cells in (("rock", rock), ("cap", ~rock)):
        kx, ky, kxy = horizontal_ratios(par, region, k0)
        s[cells, 0] = kx * sve[cells]
        s[cells, 1] = ky * sve[cells]
        s[cells, 3] = kxy * sve[cells]
    s[:, 2] = sve
    return s


def log_value(path, pattern, what):
    """The number a line of the run's log gives (pattern's group 1)."""
    with open(path + ".log") as f:
        m = re.search(pattern, f.read())
    if not m:
        raise ValueError(f"{path}.log: no line on {what}")
    return float(m.group(1))


def imbalance(path):
    return log_value(path, r"out of equilibrium.*?: ([0-9.eE+-]+) of the largest nodal weight", "the imbalance")


def step0_displacement(path):
    return log_value(path, r"max \|u\| of step 0 = ([0-9.eE+-]+) m", "step 0's displacement")


def check_column(path):
    run = open_run(path)
    par = run.parameters()
    fails = 0
    r = imbalance(path)
    fails += r > 1e-10
    print(f"{'FAIL' if r > 1e-10 else 'ok'}: in-situ imbalance {r:.2e} of the largest nodal weight (tol 1e-10)")
    z = run.cell_centres()[:, 2]
    expect = column_state(par, z)
    g, _, _, _, rho = in_situ(par)
    u_scale = g * max(rho.values()) / min(float(m["young"]) for m in par["material"])
    worst_u, worst_s = 0.0, 0.0
    for step in range(len(run.steps)):
        worst_u = max(worst_u, np.abs(run.field("displacement", step)).max() / u_scale)
        worst_s = max(worst_s, np.abs(run.field("stress", step) - expect).max() / np.abs(expect).max())
    u0 = step0_displacement(path) / u_scale
    for what, err in (("step 0's balancing displacement / (rho g H^2 / E)", u0),
                      ("displacement / (rho g H^2 / E)", worst_u), ("stress against lithostatic", worst_s)):
        fails += err > 1e-9
        print(f"{'FAIL' if err > 1e-9 else 'ok'}: {len(run.steps)} steps, {len(z)} cells: {what} {err:.2e} "
              f"(tol 1e-9)")
    return 1 if fails else 0


def biot_state(par, z):
    """(total stress (n, 6), pore pressure (n,)) in situ of the Biot column."""
    g, surface, p0, k0, rho = in_situ(par)
    mats = {m["region"]: m for m in par["material"]}
    b = np.where(z < 0.6, float(mats["rock"].get("biot", 1.0)), float(mats["cap"].get("biot", 1.0)))
    sv = -(surface + g * (rho["cap"] * (1.0 - np.maximum(z, 0.6)) + rho["rock"] * np.maximum(0.6 - z, 0.0)))
    p = p0(z) * np.ones_like(z)
    k = np.where(z < 0.6, k0["rock"], k0["cap"])
    s = np.zeros((len(z), 6))
    s[:, 0] = s[:, 1] = k * (sv + b * p) - b * p
    s[:, 2] = sv
    return s, p


def check_biot_column(path):
    run = open_run(path)
    par = run.parameters()
    s_exp, p_exp = biot_state(par, run.cell_centres()[:, 2])
    g, _, _, _, rho = in_situ(par)
    u_scale = g * max(rho.values()) / min(float(m["young"]) for m in par["material"])
    p_scale = 1000.0 * g
    eu = max(np.abs(run.field("displacement", k)).max() for k in range(len(run.steps))) / u_scale
    ep = max(np.abs(run.field("pressure_change", k)).max() for k in range(len(run.steps))) / p_scale
    ept = max(np.abs(run.field("pressure", k) - p_exp).max() for k in range(len(run.steps))) / p_scale
    es = max(np.abs(run.field("stress", k) - s_exp).max() for k in range(len(run.steps))) / np.abs(s_exp).max()
    bad = max(eu, ep, ept, es) > 1e-9
    print(f"{'FAIL' if bad else 'ok'}: {len(run.steps)} steps: displacement {eu:.1e} of rho g H^2/E, pressure change "
          f"{ep:.1e} and total pressure against hydrostatic {ept:.1e} of rho_f g H, total stress against "
          f"lithostatic {es:.1e} (tol 1e-9)")
    return 1 if bad else 0


def check_biot_superposition(path, dry_path):
    run, dry = open_run(path), open_run(dry_path)
    s_exp, p_exp = biot_state(run.parameters(), run.cell_centres()[:, 2])
    worst = 0.0
    for k in range(len(run.steps)):
        ud = dry.field("displacement", k)
        pd = dry.field("pressure", k)
        sd = dry.field("stress", k)
        worst = max(worst, np.abs(run.field("displacement", k) - ud).max() / np.abs(ud).max(),
                    np.abs(run.field("pressure_change", k) - pd).max() / np.abs(pd).max(),
                    np.abs(run.field("pressure", k) - p_exp - pd).max() / np.abs(pd).max(),
                    np.abs(run.field("stress", k) - s_exp - sd).max() / np.abs(sd).max())
    bad = worst > 1e-7
    print(f"{'FAIL' if bad else 'ok'}: {len(run.steps)} steps (undrained and two drained): displacement, pressure "
          f"change, total pressure - p0 and total stress - in situ against the dry run: {worst:.1e} (tol 1e-7)")
    return 1 if bad else 0


def check_superposition(path, dry_path):
    run, dry = open_run(path), open_run(dry_path)
    expect = column_state(run.parameters(), run.cell_centres()[:, 2])
    u, ud = run.field("displacement"), dry.field("displacement")
    s, sd = run.field("stress"), dry.field("stress")
    eu = np.abs(u - ud).max() / np.abs(ud).max()
    es = np.abs(s - expect - sd).max() / np.abs(sd).max()
    fails = 0
    for what, err in (("displacement = the dry run's", eu), ("stress = the dry run's + in situ", es)):
        fails += err > 1e-7
        print(f"{'FAIL' if err > 1e-7 else 'ok'}: {what}: relative difference {err:.2e} (tol 1e-7)")
    return 1 if fails else 0


def check_flat_fault(path):
    run = open_run(path)
    par = run.parameters()
    _, _, p0, _, _ = in_situ(par)
    expect = column_state(par, np.array([0.6]))[0, 2]
    tn = run.field("fractures/normal_traction")
    ts = run.field("fractures/shear_traction")
    slip = run.field("fractures/slip")
    en = np.abs(tn - expect).max() / abs(expect)
    et = np.abs(ts).max() / abs(expect)
    fails = (en > 1e-9) + (et > 1e-9) + (np.abs(slip).max() > 1e-12)
    print(f"{'FAIL' if fails else 'ok'}: {len(tn)} elements: t_N against sigma'_v(0.6) = {expect:.6e} Pa: {en:.2e}, "
          f"|t_T| {et:.2e} of it (tol 1e-9), max slip {np.abs(slip).max():.2e} m (tol 1e-12)")
    return 1 if fails else 0


def check_dip_fault(path, surface, rho, k0, top):
    run = open_run(path)
    g = float(run.parameters()["geostatic"][0].get("gravity", 9.81))
    c = run.field("fractures/center", 0)
    n = run.field("fractures/normal", 0)
    tn = run.field("fractures/normal_traction", 0)
    ts = run.field("fractures/shear_traction", 0)
    sv = -(surface + g * rho * (top - c[:, 2]))
    stress = np.zeros((len(c), 3, 3))
    stress[:, 0, 0] = k0 * sv
    stress[:, 1, 1] = k0 * sv
    stress[:, 2, 2] = sv
    tr = np.einsum("kij,kj->ki", stress, n)
    tne = np.einsum("ki,ki->k", tr, n)
    tse = tr - tne[:, None] * n
    # each element's vertical extent, from the fault's box-cell geometry: the
    # element's in-plane size along the dip times the dip's sine
    dz = element_dz(run, c)
    err = np.maximum(np.abs(tn - tne), np.linalg.norm(ts - tse, axis=1)) / (rho * g * dz)
    slip = np.abs(run.field("fractures/slip")).max()
    fails = (err.max() > 0.25) + (slip > 1e-12)
    print(f"{'FAIL' if fails else 'ok'}: {len(c)} elements, in-situ |t_T|/|t_N| {np.abs(tse).max() / np.abs(tne).max():.3f}: "
          f"step 0 traction against the in-situ one at the centre: largest {err.max():.3f} of rho g dz (tol 0.25); "
          f"slip at the last step {slip:.2e} m (tol 1e-12)")
    return 1 if fails else 0


def element_dz(run, centres):
    """Vertical extent of each fault element: that of the cell face nearest to its centre."""
    conn, xyz = run.conn, run.coords
    faces = [(0, 1, 2, 3), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    quads = np.concatenate([conn[:, f] for f in faces])
    qc = xyz[quads].mean(axis=1)
    out = np.empty(len(centres))
    for i, x in enumerate(centres):
        k = np.argmin(np.linalg.norm(qc - x, axis=1))
        z = xyz[quads[k], 2]
        out[i] = z.max() - z.min()
    return out


def main():
    a = sys.argv[1:]
    if not a:
        print(__doc__, file=sys.stderr)
        return 2
    if a[0] == "column":
        return check_column(a[1])
    if a[0] == "superposition":
        return check_superposition(a[1], a[2])
    if a[0] == "flat_fault":
        return check_flat_fault(a[1])
    if a[0] == "biot_column":
        return check_biot_column(a[1])
    if a[0] == "biot_superposition":
        return check_biot_superposition(a[1], a[2])
    if a[0] == "dip_fault":
        return check_dip_fault(a[1], *map(float, a[2:6]))
    print(f"unknown check {a[0]}", file=sys.stderr)
    return 2


if __name__ == "__main__":
    script_main(main)
