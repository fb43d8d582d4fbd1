"""Compare a geoblock run of Cryer's problem (a sphere octant) with the
analytical solution (postproc/analytical.py, class Cryer).

usage: check_cryer.py DIR PREFIX [--tol TOL] [--times T1,T2,...]
The material is the run's first &material, the load S the &boundary of
type 'normal_traction' (S = -normal_traction), the radius R the largest
distance of a mesh node from the origin (the centre), all from the run's
output (PREFIX_parameters.nml, the mesh). Checks:
- the undrained step (t = 0): p = p0 = B S in every cell and u = -S x/(3 K_u)
  at every node (uniform stress: exact for Q1 on the faceted sphere, whose
  faces carry -S times their own normals) to 1e-8 of p0 and of the drained
  surface displacement S R/(3 K);
- the centre cell (the cell at the origin): its pressure p_h(t) / p0 against
  the analytical centre pressure p(0, t) / p0 at the steps nearest to the
  dimensionless times T = c t / R^2 given, and at every step:
  |p_h - p| / p0 <= TOL;
- the Mandel-Cryer rise: the largest p_h / p0 of the run is above 1 and
  within TOL of the analytical largest value over the same steps.
The centre cell's history is read from the probe file PREFIX_probes.csv
(every step) when a &probe at the origin has the field p, else from the
field outputs.
Prints one line per check; exits 1 on a failure."""
import argparse
import csv
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "postproc"))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import numpy as np  # noqa: E402
from analytical import Cryer, PoroParams  # noqa: E402
from geoblock_h5 import Run, script_main  # noqa: E402
from vreport import record  # noqa: E402


def problem(run):
    """The Cryer problem of a run: material, radius and load from its output."""
    par = run.parameters()
    loads = [bc for bc in par.get("boundary", []) if bc.get("type") == "normal_traction"]
    if len(loads) != 1:
        raise ValueError(f"{run.dir}: expected one &boundary of type 'normal_traction', found {len(loads)}")
    radius = float(np.max(np.linalg.norm(run.coords, axis=1)))
    return Cryer(PoroParams.from_namelist(par["material"][0]), radius, -float(loads[0]["normal_traction"]))


def centre_history(run, c):
    """Times [s] and pressures [Pa] of the cell at the origin: the probe
    file's column of a &probe at the origin with field p, or the outputs."""
    for pr in run.parameters().get("probe", []):
        fields = pr.get("fields", [])
        fields = [fields] if isinstance(fields, str) else fields
        at = [pr.get(k, None) for k in ("x", "y", "z")]
        if "p" in fields and all(v is not None and float(v) == 0.0 for v in at):
            with open(os.path.join(run.dir, run.prefix + "_probes.csv")) as f:
                rows = list(csv.reader(f))
            k = rows[0].index(f"{pr['name']}:p [Pa]")
            return np.array([float(r[1]) for r in rows[1:]]), np.array([float(r[k]) for r in rows[1:]])
    corner = int(np.argmin(np.linalg.norm(run.coords, axis=1)))
    cells = np.nonzero(np.any(run.conn == corner, axis=1))[0]
    if np.linalg.norm(run.coords[corner]) > 1e-12 * c.R or len(cells) != 1:
        raise ValueError(f"{run.dir}: no single cell at the origin (the centre of the sphere)")
    times = run.times()
    return times, np.array([run.field("pressure", i)[cells[0]] for i in range(len(times))])


def constant_step(run):
    """The run's time step [s] when every step has it (&time dt without growth,
    no times list), else None."""
    tm = run.parameters()["time"][0]
    if "times" in tm or float(tm.get("dt_growth", 1)) != 1.0 or not tm.get("undrained", True):
        return None
    return float(tm["dt"])


def exact_fields(c, dt=None):
    """p(x, t) and u(x, t) of Cryer problem c at points x (n, 3) [m], for
    orders.py; with dt, the implicit Euler solution of steps dt."""
    def radius(x):
        return np.minimum(np.linalg.norm(x, axis=1), c.R)

    def pressure(x, t):
        return c.pressure(radius(x), t, dt=dt)

    def displacement(x, t):
        r = radius(x)
        ur = c.displacement(r, t, dt=dt)
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(r[:, None] > 0, x * (ur / np.where(r > 0, r, 1.0))[:, None], 0.0)
    return pressure, displacement


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dir")
    ap.add_argument("prefix")
    ap.add_argument("--tol", type=float, default=0.02)
    ap.add_argument("--times", default="0.01,0.02,0.045,0.1,0.15,0.2")
    a = ap.parse_args()
    run = Run(a.dir, a.prefix)
    c = problem(run)
    par = c.params
    ok = True

    p = run.field("pressure", 0)
    u = run.field("displacement", 0)
    u_exact = -c.S * run.coords / (3.0 * par.K_u)
    ep = np.max(np.abs(p - c.p0)) / c.p0
    eu = np.max(np.abs(u - u_exact)) / (c.S * c.R / (3.0 * par.K_dr))
    good = ep <= 1e-8 and eu <= 1e-8
    record("Cryer sphere, undrained step", "pressure B S (largest relative error)", ep, 1e-8)
    record("Cryer sphere, undrained step", "displacement -S x / (3 K_u) (largest relative error)", eu, 1e-8)
    ok = ok and good
    print(f"undrained step: max |p - B S| / (B S) = {ep:.2e}, max |u + S x/(3 K_u)| / (S R/(3 K)) = {eu:.2e} "
          f"(tol 1e-8) {'ok' if good else 'FAIL'}")

    times, centre = centre_history(run, c)
    T = c.time_factor(times)
    centre = centre / c.p0
    exact = c.centre_pressure(times) / c.p0
    print(f"centre cell: R = {c.R:g} m, S = {c.S:g} Pa, p0 = B S = {c.p0:.6g} Pa, c = {c.c:.4g} m^2/s, "
          f"{len(times) - 1} steps to T = {T[-1]:.4f}")
    for target in [float(v) for v in a.times.split(",")]:
        i = int(np.argmin(np.abs(T - target)))
        err = abs(centre[i] - exact[i])
        good = err <= a.tol
        ok = ok and good
        record(f"Cryer sphere, T = {T[i]:.4f}", "centre pressure |p_h - p| / p0", err, a.tol)
        print(f"T = {T[i]:.4f}: centre p_h / p0 = {centre[i]:.4f}, analytical {exact[i]:.4f}, "
              f"|difference| = {err:.4f} (tol {a.tol:g}) {'ok' if good else 'FAIL'}")
    err = np.abs(centre - exact)
    i = int(np.argmax(err))
    good = err[i] <= a.tol
    ok = ok and good
    record("Cryer sphere, every step", "centre pressure |p_h - p| / p0 (largest)", err[i], a.tol)
    print(f"every step: largest |p_h - p| / p0 = {err[i]:.4f} at T = {T[i]:.4f} (tol {a.tol:g}) "
          f"{'ok' if good else 'FAIL'}")
    k, ke = int(np.argmax(centre)), int(np.argmax(exact))
    good = centre[k] > 1.0 and abs(centre[k] - exact[ke]) <= a.tol
    ok = ok and good
    print(f"Mandel-Cryer rise: largest centre p_h / p0 = {centre[k]:.4f} at T = {T[k]:.4f}, analytical "
          f"{exact[ke]:.4f} at T = {T[ke]:.4f} (tol {a.tol:g}) {'ok' if good else 'FAIL'}")
    return 0 if ok else 1


if __name__ == "__main__":
    script_main(main)
