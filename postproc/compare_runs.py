#!/usr/bin/env python3
"""Compare two geoblock runs of the same mesh field by field at one output
step: did a change of solver, rank count or build move the result, and by
how much?

    python3 postproc/compare_runs.py out/a/contact out/b/contact
    python3 postproc/compare_runs.py out/np1/flow out/np2/flow --tol 1e-8
    python3 postproc/compare_runs.py RUN_A RUN_B --step 3

Each argument is the output directory plus prefix (as in &output). The step
is the last one unless --step says which (0-based, as in the file names);
both runs must have written it at the same time. Every field of the step
file is compared after matching cells by their centres and interface
elements by their centres and faults, so runs on different rank counts
(other partitions, other global numbering) compare: nodal fields at each
cell's corners (nodes split at a fault stay on their side), cell and
fracture fields per cell or element. For each float field the table gives
the largest |A|, the largest |A - B| and their ratio; integer fields (the
stick/slip/open status, the fault, the region) give the number of cells or
elements that differ. The partition ('rank') is left out.

With --tol the script fails (exit status 1) when a float field differs by
more than tol times its largest |A| or any integer field differs, naming
them; without it the table is the result (exit status 0). Needs numpy and
h5py.
"""
import argparse
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from geoblock_h5 import Run, coordinate_order, script_main  # noqa: E402

SKIP = {"rank", "fractures/rank"}
FRACTURE_GEOMETRY = {"fractures/center", "fractures/normal", "fractures/tangent1", "fractures/area"}


def open_run(arg):
    directory, prefix = os.path.split(os.path.normpath(arg))
    run = Run(directory or ".", prefix)
    if not run.steps:
        raise ValueError(f"{arg}: the run wrote no output step")
    return run


def step_file(run, step, arg):
    if not -len(run.steps) <= step < len(run.steps):
        raise ValueError(f"{arg}: no output step {step} (it wrote {len(run.steps)})")
    return run.steps[step]


def datasets(path):
    """name -> array of every dataset of a step file."""
    out = {}
    with h5py.File(path, "r") as f:
        f.visititems(lambda name, obj: out.__setitem__(name, np.array(obj))
                     if isinstance(obj, h5py.Dataset) else None)
        time = float(f.attrs["time"])
    return out, time


def fracture_order(fields):
    """Interface elements by fault, then centre (rounded)."""
    c = np.round(fields["fractures/center"], 9)
    return np.lexsort((c[:, 2], c[:, 1], c[:, 0], fields["fractures/fault"]))


def matched(run, fields):
    """Every compared field in an order both runs share."""
    cells = coordinate_order(run.cell_centres())
    conn = run.conn[cells]
    n_nodes, n_cells = len(run.coords), len(run.conn)
    frac = fracture_order(fields) if "fractures/center" in fields else None
    out = {}
    for name, a in fields.items():
        if name in SKIP:
            continue
        if name.startswith("fractures/"):
            out[name] = a[frac]
        elif a.shape[0] == n_nodes:
            out[name] = a[conn]          # (cells, 8 corners, components)
        elif a.shape[0] == n_cells:
            out[name] = a[cells]
    return out


def compare(fa, fb, tol):
    """Table lines and the names beyond tol."""
    lines, beyond = [], []
    width = max(len(n) for n in fa)
    for name in sorted(fa):
        a, b = fa[name], fb.get(name)
        if b is None:
            lines.append(f"{name:<{width}}  only in A")
            beyond.append(name)
            continue
        if a.shape != b.shape:
            raise ValueError(f"field {name} has {a.shape} entries in A and {b.shape} in B (another mesh?)")
        if np.issubdtype(a.dtype, np.integer):
            differ = np.any(a != b, axis=tuple(range(1, a.ndim))) if a.ndim > 1 else a != b
            extra = ""
            if name == "fractures/status":
                ca = "/".join(str(int(np.sum(a == s))) for s in range(3))
                cb = "/".join(str(int(np.sum(b == s))) for s in range(3))
                extra = f"  (stick/slip/open {ca} against {cb})"
            lines.append(f"{name:<{width}}  {int(differ.sum())} of {len(a)} differ{extra}")
            if differ.any():
                beyond.append(name)
            continue
        scale = float(np.max(np.abs(a))) if a.size else 0.0
        diff = float(np.max(np.abs(a - b))) if a.size else 0.0
        if not (np.isfinite(scale) and np.isfinite(diff)):
            raise ValueError(f"field {name} holds a NaN or an infinity")
        rel = diff / scale if scale > 0.0 else (0.0 if diff == 0.0 else float("inf"))
        lines.append(f"{name:<{width}}  max|A| {scale:11.4e}  max|A-B| {diff:11.4e}  relative {rel:9.2e}")
        if tol is not None and rel > tol and name not in FRACTURE_GEOMETRY:
            beyond.append(name)
    for name in sorted(set(fb) - set(fa)):
        lines.append(f"{name:<{width}}  only in B")
        beyond.append(name)
    return lines, beyond


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("run_a", help="output directory/prefix of run A (the reference)")
    ap.add_argument("run_b", help="output directory/prefix of run B")
    ap.add_argument("--step", type=int, default=-1, help="output step (default: the last)")
    ap.add_argument("--tol", type=float, default=None,
                    help="fail when a field differs by more than tol times its largest |A| (relative)")
    args = ap.parse_args()
    if args.tol is not None and not args.tol >= 0.0:
        raise ValueError(f"--tol must be >= 0 (got {args.tol})")
    ra, rb = open_run(args.run_a), open_run(args.run_b)
    if len(ra.conn) != len(rb.conn):
        raise ValueError(f"the runs have other meshes: {len(ra.conn)} cells in A, {len(rb.conn)} in B")
    pa, pb = step_file(ra, args.step, args.run_a), step_file(rb, args.step, args.run_b)
    fields_a, ta = datasets(pa)
    fields_b, tb = datasets(pb)
    if abs(ta - tb) > 1e-12 * max(1.0, abs(ta)):
        raise ValueError(f"the steps are at other times: {ta:g} s in A ({pa}), {tb:g} s in B ({pb})")
    print(f"A: {pa}\nB: {pb}\nt = {ta:g} s")
    lines, beyond = compare(matched(ra, fields_a), matched(rb, fields_b), args.tol)
    print("\n".join(lines))
    if args.tol is None:
        return 0
    if beyond:
        print(f"beyond {args.tol:g}: {', '.join(beyond)}")
        return 1
    print(f"every field within {args.tol:g}")
    return 0


if __name__ == "__main__":
    script_main(main)
