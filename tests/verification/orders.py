"""Observed convergence orders under mesh refinement, as a table.

usage: orders.py PROBLEM T_CHECK MIN_P MIN_U [--min-pm MIN_PM] DIR1 DIR2 DIR3 ...
PROBLEM: terzaghi, mandel or cryer (the runs' output prefix), DIR1... runs
of it on refined meshes (coarse first) with the same time steps. The
material, geometry and load come from each run's output (its
PREFIX_parameters.nml and mesh), the exact solution from
postproc/analytical.py. At the output time nearest to T_CHECK [s] the
relative L2 errors over the meshed domain,

    e_p = ||p_h - p|| / ||p||   (p_h: the P0 cell pressures),
    e_u = ||u_h - u|| / ||u||   (u_h: the Q1 interpolation of the nodal displacements),

are integrated by a 3 x 3 x 3 Gauss rule on every hexahedron through its
trilinear map (exact for the discrete fields, and for the exact ones accurate
to well below the discretization errors measured here), together with

    e_pm = ||p_h - pi_0 p|| / ||p||   (pi_0 p: the exact cell means, same rule),

the distance to the cell means, where P0 pressures of mixed methods may
converge faster than in L2 (superconvergence). For Cryer's problem run with
constant steps the exact solution is the implicit Euler series of
analytical.Cryer (the same steps, exact in space), so that the table shows
the spatial error alone; Terzaghi and Mandel take the analytical solution,
with steps small enough that the spatial error dominates. The order between two meshes
is log(e_coarse / e_fine) / log(h_coarse / h_fine), h: the cell size along
the column (Terzaghi: H / nz), across the slab (Mandel: a / nx), or the
largest cell diameter (Cryer). Prints the table (markdown) and exits 1 when
an order is below its minimum (MIN_P for e_p, MIN_U for e_u, MIN_PM for
e_pm if given) or the runs' times differ.
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "postproc"))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import numpy as np  # noqa: E402
from analytical import Mandel, PoroParams, Terzaghi  # noqa: E402
from check_cryer import constant_step, exact_fields, problem as cryer_problem  # noqa: E402
from geoblock_h5 import Run, script_main  # noqa: E402
from plot_mandel import plate_stress  # noqa: E402
from plot_terzaghi import top_load  # noqa: E402
from vreport import record  # noqa: E402

_REF = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                 [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], dtype=float)


def _gauss_hex(n=3):
    """Shape functions N (q, 8), their reference derivatives dN (q, 3, 8) and
    weights w (q) of the n^3-point Gauss rule on [-1, 1]^3."""
    g, gw = np.polynomial.legendre.leggauss(n)
    pts = np.array([[a, b, c] for c in g for b in g for a in g])
    w = np.array([wa * wb * wc for wc in gw for wb in gw for wa in gw])
    f = 1.0 + pts[:, None, :] * _REF[None, :, :]                # (q, 8, 3)
    N = f.prod(axis=2) / 8.0
    dN = np.empty((len(pts), 3, 8))
    for d in range(3):
        others = [e for e in range(3) if e != d]
        dN[:, d, :] = _REF[None, :, d] * f[:, :, others[0]] * f[:, :, others[1]] / 8.0
    return N, dN, w


def errors(run, step, p_exact, u_exact):
    """(time, e_p, e_pm, e_u) of output step `step` of a Run."""
    N, dN, w = _gauss_hex()
    X = run.coords[run.conn]                                     # (cells, 8, 3)
    xq = np.einsum("qa,cak->cqk", N, X)                          # (cells, q, 3)
    jac = np.einsum("qra,cak->cqrk", dN, X)
    dv = np.linalg.det(jac) * w[None, :]                         # (cells, q)
    t = run.times()[step]
    pts = xq.reshape(-1, 3)
    pe = np.asarray(p_exact(pts, t), dtype=float).reshape(dv.shape)
    ue = np.asarray(u_exact(pts, t), dtype=float).reshape(dv.shape + (3,))
    ph = run.field("pressure", step)[:, None]
    uh = np.einsum("qa,cak->cqk", N, run.field("displacement", step)[run.conn])
    norm_p = np.sqrt(np.sum(pe ** 2 * dv))
    e_p = np.sqrt(np.sum((ph - pe) ** 2 * dv)) / norm_p
    means = np.sum(pe * dv, axis=1) / np.sum(dv, axis=1)
    e_pm = np.sqrt(np.sum((ph[:, 0] - means) ** 2 * np.sum(dv, axis=1))) / norm_p
    e_u = np.sqrt(np.sum(np.sum((uh - ue) ** 2, axis=2) * dv) / np.sum(np.sum(ue ** 2, axis=2) * dv))
    return t, e_p, e_pm, e_u


def order_table(title, rows, minimum):
    """Print the table of errors and orders of rows (h, t, e_p, e_pm, e_u),
    coarse to fine, and a verdict line; minimum: the smallest order accepted
    between successive meshes for 'p', 'u' and optionally 'pm'. Returns True
    when every order passes and the rows' times agree."""
    print(f"{title}: relative L2 errors at t = {rows[-1][1]:.6g} s")
    print("| h [m] | pressure e_p | order | pressure vs cell means e_pm | order | displacement e_u | order |")
    print("|---|---|---|---|---|---|---|")
    orders = {key: [] for key in ("p", "pm", "u")}
    for k, (h, t, *e) in enumerate(rows):
        cols = [f"{h:.4g}"]
        for j, key in enumerate(("p", "pm", "u")):
            cols.append(f"{e[j]:.3e}")
            if k > 0:
                orders[key].append(np.log(rows[k - 1][2 + j] / e[j]) / np.log(rows[k - 1][0] / h))
            cols.append(f"{orders[key][-1]:.2f}" if k > 0 else "")
        print("| " + " | ".join(cols) + " |")
    ok = all(min(orders[key]) >= v for key, v in minimum.items())
    names = {"p": "pressure e_p", "pm": "pressure against cell means e_pm", "u": "displacement e_u"}
    for k in range(1, len(rows)):
        for j, key in enumerate(("p", "pm", "u")):
            o = orders[key][k - 1]
            record(f"{title}, h = {rows[k - 1][0]:.4g} -> {rows[k][0]:.4g} m", names[key] + " (relative L2)",
                   rows[k][2 + j], f"order >= {minimum[key]:g}" if key in minimum else "", f"{o:.2f}",
                   passed=o >= minimum.get(key, -1e300))
    verdict = f"{title}: observed orders " + ", ".join(
        f"e_{key} " + " ".join(f"{o:.2f}" for o in orders[key]) + (f" (min {minimum[key]:g})" if key in minimum else "")
        for key in ("p", "pm", "u"))
    if len({round(r[1], 9) for r in rows}) != 1:
        verdict += "; the runs' output times differ: " + ", ".join(f"{r[1]:.6g}" for r in rows)
        ok = False
    print(verdict + (" ok" if ok else " FAIL"))
    return ok


def terzaghi(run):
    """Exact fields and cell size of a Terzaghi column (base at the mesh's lowest z)."""
    par = run.parameters()
    z0 = float(run.coords[:, 2].min())
    height = float(run.coords[:, 2].max()) - z0
    tz = Terzaghi(PoroParams.from_namelist(par["material"][0]), height, top_load(par))
    nz = len(np.unique(np.round(run.cell_centres()[:, 2], 9)))

    def displacement(x, t):
        u = np.zeros_like(x)
        u[:, 2] = tz.displacement(x[:, 2] - z0, t)
        return u
    return (lambda x, t: tz.pressure(x[:, 2] - z0, t)), displacement, height / nz


def mandel(run):
    """Exact fields and cell size of Mandel's quarter model (0 < x < a, 0 < y < b)."""
    par = run.parameters()
    a, b = float(run.coords[:, 0].max()), float(run.coords[:, 1].max())
    m = Mandel.from_traction(PoroParams.from_namelist(par["material"][0]), a, b, plate_stress(par, None))
    nx = len(np.unique(np.round(run.cell_centres()[:, 0], 9)))

    def displacement(x, t):
        return np.stack([m.displacement_x(x[:, 0], t), m.displacement_y(x[:, 1], t), 0 * x[:, 2]], axis=1)
    return (lambda x, t: m.pressure(x[:, 0], t)), displacement, a / nx


def cryer(run):
    """Exact fields and largest cell diameter of a sphere octant: with
    constant steps the implicit Euler series (the run's own steps, exact in
    space), so that the errors are the spatial ones alone."""
    p_exact, u_exact = exact_fields(cryer_problem(run), constant_step(run))
    x = run.coords[run.conn]
    diam = max(float(np.max(np.linalg.norm(x[:, i] - x[:, j], axis=1))) for i in range(8) for j in range(i))
    return p_exact, u_exact, diam


PROBLEMS = {"terzaghi": terzaghi, "mandel": mandel, "cryer": cryer}


def main():
    import argparse
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("problem", choices=sorted(PROBLEMS))
    ap.add_argument("t_check", type=float, help="time [s] (the nearest output step)")
    ap.add_argument("min_p", type=float, help="smallest order accepted for e_p")
    ap.add_argument("min_u", type=float, help="smallest order accepted for e_u")
    ap.add_argument("dirs", nargs="+", help="output directories, coarse to fine")
    ap.add_argument("--min-pm", type=float, help="smallest order accepted for e_pm")
    a = ap.parse_args()
    runs = [Run(d, a.problem) for d in a.dirs]
    rows = []
    for run in runs:
        p_exact, u_exact, h = PROBLEMS[a.problem](run)
        step = int(np.argmin(np.abs(run.times() - a.t_check)))
        rows.append((h,) + errors(run, step, p_exact, u_exact))
    minimum = {"p": a.min_p, "u": a.min_u}
    if a.min_pm is not None:
        minimum["pm"] = a.min_pm
    return 0 if order_table(a.problem, rows, minimum) else 1


if __name__ == "__main__":
    script_main(main)
