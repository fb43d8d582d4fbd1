"""Surface displacement above a depleted box-shaped reservoir against
Geertsma's nucleus-of-strain solution (Geertsma 1973, J. Petroleum
Technology 25: a small volume dV at depth c with a pore pressure change dp
in a homogeneous elastic half-space moves the free surface by
u = c_m (1 - nu) dp dV / pi * (x - xi, y - eta, c) / R^3, R the distance,
c_m = (1 + nu)(1 - 2 nu) / (E (1 - nu)) the uniaxial compaction coefficient
and b = 1), integrated over the reservoir [-a, a]^2 x [-z_bot, -z_top] by
Gauss-Legendre quadrature (40 x 40 x 4 points: the integrand is smooth at
the surface, 1e-10 relative).

usage: check_geertsma.py RUN E NU DP A Z_TOP Z_BOT RMAX TOL
RUN: output directory/prefix of a quarter model (symmetry planes x = 0 and
y = 0, top z = 0). Every top-surface node within RMAX of the axis (the
symmetry planes included): |u_z - u_z,a| and |u_h - u_h,a| (horizontal
vector) at most TOL times the analytical centre subsidence. Prints one
line; exits 1 on a failure."""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "postproc"))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import numpy as np  # noqa: E402
from geoblock_h5 import Run, script_main  # noqa: E402
from vreport import record  # noqa: E402


def geertsma(points, e, nu, dp, a, z_top, z_bot):
    cm = (1 + nu) * (1 - 2 * nu) / (e * (1 - nu))
    gx, wx = np.polynomial.legendre.leggauss(40)
    gz, wz = np.polynomial.legendre.leggauss(4)
    xi = a * gx
    wxi = a * wx
    c = 0.5 * (z_top + z_bot) + 0.5 * (z_bot - z_top) * gz
    wc = 0.5 * (z_bot - z_top) * wz
    out = np.zeros((len(points), 3))
    for k, p in enumerate(points):
        dx = p[0] - xi[:, None, None]
        dy = p[1] - xi[None, :, None]
        cc = c[None, None, :]
        w = wxi[:, None, None] * wxi[None, :, None] * wc[None, None, :]
        r3 = (dx * dx + dy * dy + cc * cc) ** 1.5
        out[k] = [np.sum(w * dx / r3), np.sum(w * dy / r3), np.sum(w * cc / r3)]
    return cm * (1 - nu) * dp / np.pi * out


def main():
    if len(sys.argv) != 10:
        print(__doc__, file=sys.stderr)
        return 2
    path = sys.argv[1]
    e, nu, dp, a, z_top, z_bot, rmax, tol = map(float, sys.argv[2:])
    run = Run(os.path.dirname(path), os.path.basename(path))
    x = run.coords
    u = run.field("displacement")
    top = np.where((np.abs(x[:, 2]) < 1e-6) & (np.hypot(x[:, 0], x[:, 1]) <= rmax))[0]
    ua = geertsma(x[top], e, nu, dp, a, z_top, z_bot)
    uz0 = abs(geertsma(np.zeros((1, 3)), e, nu, dp, a, z_top, z_bot)[0, 2])
    ez = np.abs(u[top, 2] - ua[:, 2]).max() / uz0
    eh = np.linalg.norm(u[top, :2] - ua[:, :2], axis=1).max() / uz0
    bad = max(ez, eh) > tol
    record(f"Geertsma's subsidence bowl, {len(top)} surface nodes", "u_z, u_h against Geertsma (largest error / the "
           "centre subsidence)", max(ez, eh), tol)
    print(f"{'FAIL' if bad else 'ok'}: {len(top)} surface nodes within {rmax:g} m: centre subsidence "
          f"{-u[top][np.argmin(np.hypot(x[top, 0], x[top, 1])), 2]:.4e} m (Geertsma {uz0:.4e}); largest error "
          f"u_z {ez:.4f}, u_h {eh:.4f} of it (tol {tol:g})")
    return 1 if bad else 0


if __name__ == "__main__":
    script_main(main)
