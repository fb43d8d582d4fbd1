"""Check the run of input/gmsh_block.nml against the oedometric (uniaxial
strain) solution: rollers on the sides and the base, top load q, gravity.
With no lateral strain, sigma_zz(z) = -q - (weight of the column above z),
sigma_xx = sigma_yy = nu / (1 - nu) sigma_zz, shear stresses zero. Q1 with
consistent loads is nodally exact in 1D and the cell-centre stress of a
quadratic displacement is exact, so the tolerance is round-off (1e-8).

usage: check_oedometer.py DIR PREFIX"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "postproc"))
import numpy as np  # noqa: E402
from geoblock_h5 import Run  # noqa: E402

q = 5.0e6                  # top load [Pa]
z_fault, top = 0.6, 1.0
w_rock, w_cap = 2.3e4, 2.5e4   # rho g [N/m^3]
nu = {1: 0.3, 2: 0.2}      # region ids in the file order: rock, cap


def sigma_zz(z):
    above_cap = np.clip(top - np.maximum(z, z_fault), 0, None)
    above_rock = np.clip(z_fault - z, 0, None)
    return -q - w_cap * above_cap - w_rock * above_rock


def main():
    run = Run(sys.argv[1], sys.argv[2])
    s = run.field("stress")          # (n_cells, 6): xx yy zz xy yz xz
    reg = run.field("region")
    zc = run.cell_centres()[:, 2]
    exact = sigma_zz(zc)
    err_zz = np.max(np.abs(s[:, 2] - exact)) / q
    lateral = np.array([nu[r] / (1 - nu[r]) for r in reg]) * exact
    err_xx = max(np.max(np.abs(s[:, 0] - lateral)), np.max(np.abs(s[:, 1] - lateral))) / q
    err_sh = np.max(np.abs(s[:, [3, 4, 5]])) / q
    ok = err_zz < 1e-8 and err_xx < 1e-8 and err_sh < 1e-8 and set(np.unique(reg)) == {1, 2}
    print(f"cells {len(zc)}, regions {sorted(set(np.unique(reg)))}: sigma_zz error {err_zz:.2e}, "
          f"lateral error {err_xx:.2e}, shear {err_sh:.2e} (relative to q, tol 1e-8)")
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
