"""Write the plate displacement of Mandel's problem as a geoblock boundary
history ("time factor" rows): the displacement-controlled form of Mandel's
problem prescribes u_y(b, t) of the analytical solution on the plate, which
then behaves as the rigid, frictionless plate under the constant force.

usage: make_mandel_history.py OUT E nu b M k mu a b_half sigma t_end [n]
(sigma: plate stress magnitude [Pa], compression; writes n log-spaced times,
plus t = 0 with the undrained value)."""
import sys

import numpy as np

from analytical import Mandel, PoroParams


def main():
    out = sys.argv[1]
    E, nu, b, M, k, mu, a, bh, sigma, t_end = map(float, sys.argv[2:12])
    n = int(sys.argv[12]) if len(sys.argv) > 12 else 400
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
    main()
