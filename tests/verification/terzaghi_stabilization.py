"""Accuracy of the pressure-jump stabilization on a compressible Terzaghi column.

usage: terzaghi_stabilization.py OFF FULL ADAPTIVE T1,T2,... MAX_RATIO_OFF MAX_RATIO_FULL
Three runs of the same column (prefix 'terzaghi'): without stabilization,
with its full (undrained incompressible) weight and with the adaptive one.
Material, height and load are read from the first run's
terzaghi_parameters.nml. At the output time nearest each dimensionless time
T = c_v t / H^2 it prints the relative L2 errors of the cell pressures
(against the exact cell averages) and the settlement error relative to the
consolidation settlement sigma0 H (1/K_v - 1/K_vu) of the three runs, and
fails unless the adaptive error is at most MAX_RATIO_OFF times the
unstabilized one and at most MAX_RATIO_FULL times the full one, and unless
the adaptive settlement error has the sign of the unstabilized one at the
first time."""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "postproc"))
import numpy as np  # noqa: E402
from analytical import PoroParams, Terzaghi  # noqa: E402
from geoblock_h5 import Run, script_main  # noqa: E402

from check_terzaghi import cell_average  # noqa: E402


def errors(d, tz, H, target):
    """Pressure relative L2 error and relative settlement error of run d at
    the output time nearest T = target."""
    run = Run(d, "terzaghi")
    times = run.times()
    i = int(np.argmin(np.abs(tz.time_factor(times) - target)))
    zc = run.cell_centres()[:, 2]
    h = H / len(np.unique(np.round(zc, 9)))
    ex = cell_average(tz, zc, h, times[i])
    ep = np.sqrt(np.sum((run.field("pressure", i) - ex) ** 2) / np.sum(ex ** 2))
    top = np.isclose(run.coords[:, 2], H)
    s = -run.field("displacement", i)[top, 2].mean()
    s_ex = -tz.displacement(np.array([H]), times[i])[0]
    s_cons = tz.sigma0 * H * (1.0 / tz.params.K_v - 1.0 / tz.params.K_vu)
    return tz.time_factor(times[i]), ep, (s - s_ex) / s_cons


def main():
    off, full, adaptive = sys.argv[1:4]
    targets = [float(x) for x in sys.argv[4].split(",")]
    max_off, max_full = float(sys.argv[5]), float(sys.argv[6])
    par = Run(off, "terzaghi").parameters()
    H = float(par["mesh"][0]["upper"][2])
    load = -float(next(bc for bc in par["boundary"] if bc.get("type") == "traction")["traction"][2])
    tz = Terzaghi(PoroParams.from_namelist(par["material"][0]), H, load)
    ok = True
    for k, target in enumerate(targets):
        (T, e_off, s_off), (_, e_full, s_full), (_, e_ad, s_ad) = \
            (errors(d, tz, H, target) for d in (off, full, adaptive))
        good = e_ad <= max_off * e_off and e_ad <= max_full * e_full and (k > 0 or np.sign(s_ad) == np.sign(s_off))
        print(f"T = {T:.4f}: pressure L2 error adaptive {e_ad:.3e}, off {e_off:.3e}, full {e_full:.3e} "
              f"(ratios {e_ad / e_off:.2f} <= {max_off:g}, {e_ad / e_full:.2f} <= {max_full:g}); settlement error "
              f"{s_ad:+.2e}, {s_off:+.2e}, {s_full:+.2e} {'ok' if good else 'FAIL'}")
        ok = ok and good
    return 0 if ok else 1


if __name__ == "__main__":
    script_main(main)
