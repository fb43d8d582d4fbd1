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
With --case, the relative L2 errors over the middle 80 % of the fracture
(|s| <= 0.8 b) are printed as 'error <quantity> <value>' lines, and --check
TOL makes the exit status nonzero when one exceeds TOL. Young's modulus and
Poisson's ratio (first &material) and, for sneddon, the pressure (first
&fault) are read from the run's <run>_parameters.nml; an option given on the
command line wins. The other analytical parameters default to those of
input/sneddon.nml and input/single_fracture.nml.
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
    return s, f("opening"), f("slip_magnitude"), f("normal_traction"), f("shear_traction_magnitude"), f("status")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run", help="output directory/prefix, e.g. out/sneddon")
    ap.add_argument("--case", choices=["sneddon", "phan"], help="analytical reference")
    ap.add_argument("--step", type=int, default=-1)
    ap.add_argument("--half-length", type=float, default=1.0, help="b [m]")
    ap.add_argument("--young", type=float, help="E [Pa] (default: the run's)")
    ap.add_argument("--poisson", type=float, help="nu (default: the run's)")
    ap.add_argument("--pressure", type=float, help="sneddon: p [Pa] (default: the run's first fault)")
    ap.add_argument("--sigma", type=float, default=1.0e7, help="phan: compression [Pa]")
    ap.add_argument("--psi", type=float, default=20.0, help="phan: crack to load angle [deg]")
    ap.add_argument("--friction", type=float, default=30.0, help="phan: friction angle [deg]")
    ap.add_argument("--check", type=float, help="fail if an error exceeds this")
    ap.add_argument("--png", help="figure file (default <run>_fracture.png)")
    args = ap.parse_args()

    run = Run(os.path.dirname(args.run) or ".", os.path.basename(args.run))
    if args.case and None in (args.young, args.poisson, args.pressure):
        par = run.parameters()
        mat = par["material"][0]
        args.young = float(mat["young"]) if args.young is None else args.young
        args.poisson = float(mat["poisson"]) if args.poisson is None else args.poisson
        if args.pressure is None:
            args.pressure = float(par["fault"][0]["pressure"]) if "fault" in par else 0.0
    s, opening, slip, tn, tt, status = fracture_fields(run, args.step)
    order = np.argsort(s)
    b = args.half_length
    mid = np.abs(s) <= 0.8 * b
    errors = {}
    ref = {}
    if args.case == "sneddon":
        ref["opening"] = sneddon_opening(s, b, args.pressure, args.young, args.poisson)
        errors["opening"] = relative_l2(opening, ref["opening"], mid)
    elif args.case == "phan":
        ref["slip"], ref["t_N"], ref["t_T"] = inclined_crack(s, b, args.sigma, args.psi, args.friction,
                                                             args.young, args.poisson)
        errors["slip"] = relative_l2(slip, ref["slip"], mid)
        errors["t_N"] = relative_l2(tn, ref["t_N"], mid)
        errors["t_T"] = relative_l2(tt, ref["t_T"], mid)
    counts = np.bincount(status.astype(int), minlength=3)    # 0 stick, 1 slip, 2 open
    print(f"elements {len(s)}  stick/slip/open {counts[0]}/{counts[1]}/{counts[2]}")
    for k, v in errors.items():
        print(f"error {k} {v:.6e}")

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
