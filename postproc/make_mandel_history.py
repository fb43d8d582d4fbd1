"""Write the plate displacement of Mandel's problem as a geoblock boundary
history ("time factor" rows): the displacement-controlled form of Mandel's
problem prescribes u_y(b, t) of the analytical solution on the plate, which
then behaves as the rigid, frictionless plate under the constant force.

usage: make_mandel_history.py OUT E nu b M k mu a b_half sigma t_end [n]
(sigma: plate stress magnitude [Pa], compression; writes n log-spaced times,
plus t = 0 with the undrained value). The header names the parameters
(plot_mandel.py reads sigma from it)."""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from analytical import Mandel, PoroParams  # noqa: E402
from geoblock_h5 import script_main  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out", help="history file to write")
    for name, what in (("E", "drained Young's modulus [Pa]"), ("nu", "drained Poisson's ratio [-]"),
                       ("b", "Biot coefficient [-]"), ("M", "Biot modulus [Pa]"), ("k", "permeability [m^2]"),
                       ("mu", "viscosity [Pa s]"), ("a", "half-width along x [m]"),
                       ("b_half", "half-height along y [m]"), ("sigma", "plate stress magnitude [Pa]"),
                       ("t_end", "last time [s]")):
        ap.add_argument(name, type=float, help=what)
    ap.add_argument("n", type=int, nargs="?", default=400, help="number of log-spaced times (default 400)")
    args = ap.parse_args()
    out, n = args.out, args.n
    E, nu, b, M, k, mu, a, bh, sigma, t_end = (args.E, args.nu, args.b, args.M, args.k, args.mu, args.a,
                                               args.b_half, args.sigma, args.t_end)
    m = Mandel.from_traction(PoroParams(E=E, nu=nu, b=b, M=M, k=k, mu=mu), a, bh, sigma)
    t = np.concatenate([[0.0], np.geomspace(t_end * 1e-6, t_end, n)])
    u = m.plate_displacement(t)
    with open(out, "w") as f:
        f.write("# Mandel plate displacement u_y(b, t) [m] (postproc/make_mandel_history.py)\n")
        f.write(f"# E={E:g} nu={nu:g} b={b:g} M={M:g} k={k:g} mu={mu:g} a={a:g} b_half={bh:g} sigma={sigma:g}\n")
        f.write(f"# c = {m.c:.6e} m^2/s, p0 = {m.p0:.6e} Pa\n")
        for ti, ui in zip(t, u):
            f.write(f"{ti:.10e} {ui:.15e}\n")


if __name__ == "__main__":
    script_main(main)
