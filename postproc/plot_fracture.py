#!/usr/bin/env python3
"""Plot the fields along a fracture of a geoblock contact run against the
analytical solution, and report the errors.

    python3 postproc/plot_fracture.py out/sneddon --case sneddon
    python3 postproc/plot_fracture.py out/single_fracture --case phan
    python3 postproc/plot_fracture.py out/myrun            (no reference)

The argument is the output directory plus prefix (as in &output). The last
output step is used (--step to choose). Positions s along the fracture are the
projections of the element centres on the mean in-plane direction m1 (the
'tangent1' field), measured from the fracture's centroid; in plane strain with
the fault extruded along z every column of elements gives the same curve.
With --case, the errors over every element of the fracture, tips included,
are printed: 'error <quantity> <value>' the relative L2 error, and for the
tractions 'maxerror <quantity> <value>' the largest relative error of an
element. The reference of an element is the analytical solution's mean over
the element's width 2b/n (n columns along the fracture), the quantity a P0
element holds. --check TOL makes the exit status nonzero when an error (L2 or
max) exceeds TOL. Every analytical
parameter comes from the run itself unless given on the command line:
Young's modulus and Poisson's ratio from the first &material of the run's
<run>_parameters.nml; for sneddon the pressure of the first &fault; for phan
the friction angle of the first &fault, the compression sigma as the
magnitude of the first 'traction' &boundary and psi as the angle between its
direction and the fracture's tangent. The half-length b is measured on the
output: the element centres span 2b less one element.
Needs numpy, h5py and (for the figure) matplotlib.
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from geoblock_h5 import Run, script_main  # noqa: E402
from fracture_analytical import sneddon_opening, inclined_crack, relative_l2  # noqa: E402


def fracture_fields(run, step):
    f = lambda name: run.field("fractures/" + name, step)  # noqa: E731
    centre, m1 = f("center"), f("tangent1")
    d = m1.mean(axis=0)
    d /= np.linalg.norm(d)
    s = (centre - centre.mean(axis=0)) @ d
    return s, d, f("opening"), f("slip_magnitude"), f("normal_traction"), f("shear_traction_magnitude"), f("status")


def half_length(s):
    """b from the element centres: n distinct positions over 2b, one element apart."""
    pos = np.unique(np.round(s, 9))
    if len(pos) < 2:
        raise SystemExit("plot_fracture.py: error: the fracture has a single column of elements; give --half-length")
    return 0.5 * (pos[-1] - pos[0]) * len(pos) / (len(pos) - 1)


def run_parameters(run, args, tangent):
    """Fill the analytical parameters not given on the command line from the run."""
    par = run.parameters()
    mat = par["material"][0]
    fault = par["fault"][0] if "fault" in par else {}
    if args.young is None:
        args.young = float(mat["young"])
    if args.poisson is None:
        args.poisson = float(mat["poisson"])
    if args.pressure is None:
        args.pressure = float(fault.get("pressure", 0.0))
    if args.friction is None:
        args.friction = float(fault.get("friction_angle", 0.0))
    if args.case == "phan" and (args.sigma is None or args.psi is None):
        loads = [b for b in par.get("boundary", []) if b.get("type") == "traction"]
        if not loads:
            raise SystemExit("plot_fracture.py: error: the run has no 'traction' &boundary; give --sigma and --psi")
        t = np.asarray(loads[0]["traction"], dtype=float)
        if args.sigma is None:
            args.sigma = float(np.linalg.norm(t))
        if args.psi is None:
            c = abs(float(t @ tangent)) / np.linalg.norm(t)
            args.psi = float(np.degrees(np.arccos(min(c, 1.0))))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run", help="output directory/prefix, e.g. out/sneddon")
    ap.add_argument("--case", choices=["sneddon", "phan"], help="analytical reference")
    ap.add_argument("--step", type=int, default=-1)
    ap.add_argument("--half-length", type=float, help="b [m] (default: measured on the run)")
    ap.add_argument("--young", type=float, help="E [Pa] (default: the run's)")
    ap.add_argument("--poisson", type=float, help="nu (default: the run's)")
    ap.add_argument("--pressure", type=float, help="sneddon: p [Pa] (default: the run's first fault)")
    ap.add_argument("--sigma", type=float, help="phan: compression [Pa] (default: the run's traction)")
    ap.add_argument("--psi", type=float, help="phan: crack to load angle [deg] (default: the run's)")
    ap.add_argument("--friction", type=float, help="phan: friction angle [deg] (default: the run's first fault)")
    ap.add_argument("--check", type=float, help="fail if an error exceeds this")
    ap.add_argument("--png", help="figure file (default <run>_fracture.png)")
    args = ap.parse_args()

    run = Run(os.path.dirname(args.run) or ".", os.path.basename(args.run))
    s, d, opening, slip, tn, tt, status = fracture_fields(run, args.step)
    if args.half_length is None:
        args.half_length = half_length(s)
    if args.case:
        run_parameters(run, args, d)
    order = np.argsort(s)
    b = args.half_length
    width = 2.0 * b / len(np.unique(np.round(s, 9)))
    errors = {}
    ref = {}
    if args.case == "sneddon":
        ref["opening"] = sneddon_opening(s, b, args.pressure, args.young, args.poisson, width)
        errors["error opening"] = relative_l2(opening, ref["opening"])
    elif args.case == "phan":
        ref["slip"], ref["t_N"], ref["t_T"] = inclined_crack(s, b, args.sigma, args.psi, args.friction,
                                                             args.young, args.poisson, width)
        errors["error slip"] = relative_l2(slip, ref["slip"])
        for key, num in (("t_N", tn), ("t_T", tt)):
            errors["error " + key] = relative_l2(num, ref[key])
            errors["maxerror " + key] = float(np.max(np.abs(num / ref[key] - 1.0)))
    counts = np.bincount(status.astype(int), minlength=3)    # 0 stick, 1 slip, 2 open
    print(f"elements {len(s)}  stick/slip/open {counts[0]}/{counts[1]}/{counts[2]}")
    for k, v in errors.items():
        print(f"{k} {v:.6e}")

    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(1, 2, figsize=(10, 4))
        panels = [(ax[0], "jump [m]", [("opening g_N", opening, "opening"), ("slip |g_T|", slip, "slip")]),
                  (ax[1], "traction [Pa]", [("t_N", tn, "t_N"), ("|t_T|", tt, "t_T")])]
        for a, ylabel, curves in panels:
            for (label, values, key), marker in zip(curves, ("o", "s")):
                a.plot(s[order], values[order], marker, ms=3, label=label)
                if key in ref:
                    a.plot(s[order], ref[key][order], "-", label=f"{key}, analytical")
            a.set_xlabel("s [m]")
            a.set_ylabel(ylabel)
            a.legend()
        fig.tight_layout()
        png = args.png or args.run + "_fracture.png"
        fig.savefig(png, dpi=120)
        print(f"figure {png}")
    except ImportError:
        print("matplotlib missing: no figure")

    if args.check is not None and any(v > args.check for v in errors.values()):
        print(f"FAILED: an error exceeds {args.check}")
        return 1
    return 0


if __name__ == "__main__":
    script_main(main)
