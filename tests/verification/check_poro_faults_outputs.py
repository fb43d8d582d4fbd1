#!/usr/bin/env python3
"""The outputs of a physics = 'poromechanics_faults' run (issue 33,
deliverable 5), checked against each other at every output step:

    check_poro_faults_outputs.py DIR PREFIX

- the mesh grid has the matrix's pressure and Darcy velocity, the fractures
  grid the fracture pressure, the leak-off, the (effective) normal
  traction, the total normal traction and the CFF; every value finite;
- the effective normal traction is the total one plus the fracture
  pressure: t_N = (t_N - p_f) + p_f;
- the CFF recomputed from the other fields and the deck's friction and
  cohesion: |tau| - (c - tan(phi) t_N), t_N = total_normal_traction +
  pressure (tau - mu (sigma_n - p_f) with sigma_n the total normal stress,
  compression positive), relative to the largest traction;
- the probe file's per-fault columns: <fault>:leakoff equals the sum of the
  leak-off of the fault's elements, <fault>:max_slip the largest
  slip_magnitude, <fault>:mean_slip the area-weighted mean slip magnitude
  (the fracture flow's element areas), at the step of the same time.

Prints one line per check ending in 'ok' or 'FAIL'; exit 1 on a failure.
"""
import csv
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "postproc"))
import h5py  # noqa: E402
import numpy as np  # noqa: E402
from geoblock_h5 import Run  # noqa: E402

MESH = ("pressure", "darcy_velocity")
FRACTURES = ("pressure", "leakoff", "normal_traction", "total_normal_traction", "shear_traction_magnitude",
             "cff", "slip_magnitude", "area", "fault")


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__.split("\n\n")[1])
    directory, prefix = sys.argv[1:]
    run = Run(directory, prefix)
    par = run.parameters()
    faults = par["fault"]
    names = [f["name"] for f in faults]
    tanphi = [math.tan(math.radians(f.get("friction_angle", 30.0))) for f in faults]
    coh = [f.get("cohesion", 0.0) for f in faults]
    with open(os.path.join(directory, prefix + "_probes.csv")) as fh:
        rows = list(csv.DictReader(fh))
    time_col = [k for k in rows[0] if k.startswith("time")][0]
    fail = 0
    missing = []
    worst = {"finite": 0, "tn": 0.0, "cff": 0.0, "leakoff": 0.0, "max_slip": 0.0, "mean_slip": 0.0}
    matched = 0
    for path in run.steps:
        with h5py.File(path, "r") as f:
            t = float(f.attrs["time"])
            missing += [n for n in MESH if n not in f] + [f"fractures/{n}" for n in FRACTURES if f"fractures/{n}" not in f]
            if missing:
                break
            for n in MESH:
                worst["finite"] += int(np.sum(~np.isfinite(np.asarray(f[n]))))
            fr = {n: np.asarray(f[f"fractures/{n}"]) for n in FRACTURES}
        for n in FRACTURES:
            worst["finite"] += int(np.sum(~np.isfinite(fr[n])))
        fault = fr["fault"].astype(int)           # 1-based, deck order
        tn = fr["total_normal_traction"] + fr["pressure"]
        scale = max(np.abs(fr["normal_traction"]).max(), np.abs(fr["shear_traction_magnitude"]).max(), 1.0)
        worst["tn"] = max(worst["tn"], np.abs(tn - fr["normal_traction"]).max() / scale)
        cff = fr["shear_traction_magnitude"] - (np.take(coh, fault - 1) - np.take(tanphi, fault - 1) * tn)
        worst["cff"] = max(worst["cff"], np.abs(cff - fr["cff"]).max() / scale)
        row = [r for r in rows if abs(float(r[time_col]) - t) <= 1e-9 * max(1.0, abs(t))]
        if not row:
            continue
        matched += 1
        row = row[-1]
        for k, name in enumerate(names):
            on = fault == k + 1
            lo = fr["leakoff"][on].sum()
            lscale = max(np.abs(fr["leakoff"][on]).sum(), 1e-300)
            worst["leakoff"] = max(worst["leakoff"], abs(float(row[f"{name}:leakoff [m3/s]"]) - lo) / lscale)
            s = fr["slip_magnitude"][on]
            sscale = max(s.max(), 1e-300)
            worst["max_slip"] = max(worst["max_slip"], abs(float(row[f"{name}:max_slip [m]"]) - s.max()) / sscale)
            mean = np.sum(fr["area"][on] * s) / np.sum(fr["area"][on])
            worst["mean_slip"] = max(worst["mean_slip"], abs(float(row[f"{name}:mean_slip [m]"]) - mean) / sscale)
    if missing:
        print(f"datasets missing at {run.steps[0] if not run.steps else path}: {', '.join(missing)} FAIL")
        return 1
    checks = [
        (f"datasets {', '.join(MESH)} (mesh) and {', '.join(FRACTURES[:6])} (fractures) at {len(run.steps)} steps, "
         f"non-finite values {worst['finite']}", worst["finite"] == 0 and len(run.steps) > 0),
        (f"effective normal traction = total + fracture pressure: largest difference {worst['tn']:.1e} "
         f"of the largest traction (tol 1e-12)", worst["tn"] <= 1e-12),
        (f"CFF = |tau| - (c - tan(phi) (total t_N + p_f)): largest difference {worst['cff']:.1e} of the largest "
         f"traction (tol 1e-12)", worst["cff"] <= 1e-12),
        (f"probes: per-fault leak-off = sum over the fault's elements at {matched} steps: largest difference "
         f"{worst['leakoff']:.1e} of the summed magnitudes (tol 1e-12)", worst["leakoff"] <= 1e-12 and matched > 0),
        (f"probes: max_slip, mean_slip (area-weighted) from the elements: largest differences "
         f"{worst['max_slip']:.1e}, {worst['mean_slip']:.1e} of the largest slip (tol 1e-12)",
         worst["max_slip"] <= 1e-12 and worst["mean_slip"] <= 1e-12),
    ]
    for text, good in checks:
        print(f"{text} {'ok' if good else 'FAIL'}")
        fail += 0 if good else 1
    return 1 if fail else 0


if __name__ == "__main__":
    sys.exit(main())
