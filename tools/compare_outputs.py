#!/usr/bin/env python3
"""Compare two output trees of geoblock runs made from the same decks on the
same number of ranks, before and after a change that must not change results
(a refactoring, a new code path for the same method).

usage: compare_outputs.py DIR_BEFORE DIR_AFTER [--tol 1e-12]

For every HDF5 file present in both trees (same relative path), every dataset
is compared: relative max-norm difference max|a - b| / max|a| (datasets of
integers must be equal). For every log file (*.log) present in both trees, the
iteration counts of the progress lines (the numbers after 'iterations',
'linear its' and 'newton') must be the same, line by line. Files present in
only one tree are listed. Prints one line per file that differs and a summary;
exits 1 when anything differs beyond the tolerance.
"""
import argparse
import os
import re
import sys

import h5py
import numpy as np

COUNT = re.compile(r"(iterations|linear its|newton)\s+(\d+)")


def files(root, ext):
    out = set()
    for base, _, names in os.walk(root):
        for n in names:
            if n.endswith(ext):
                out.add(os.path.relpath(os.path.join(base, n), root))
    return out


def compare_h5(a_path, b_path, tol):
    """Return a list of (dataset, message) differences."""
    bad = []
    with h5py.File(a_path, "r") as fa, h5py.File(b_path, "r") as fb:
        names_a, names_b = [], []
        fa.visititems(lambda n, o: names_a.append(n) if isinstance(o, h5py.Dataset) else None)
        fb.visititems(lambda n, o: names_b.append(n) if isinstance(o, h5py.Dataset) else None)
        for n in sorted(set(names_a) ^ set(names_b)):
            bad.append((n, "only in " + ("before" if n in names_a else "after")))
        for n in sorted(set(names_a) & set(names_b)):
            x, y = fa[n][()], fb[n][()]
            if np.shape(x) != np.shape(y):
                bad.append((n, f"shape {np.shape(x)} vs {np.shape(y)}"))
                continue
            if np.issubdtype(np.asarray(x).dtype, np.floating):
                if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
                    bad.append((n, "non-finite values"))
                    continue
                scale = max(float(np.max(np.abs(x))) if np.size(x) else 0.0, 1e-300)
                rel = float(np.max(np.abs(x - y))) / scale if np.size(x) else 0.0
                if rel > tol:
                    bad.append((n, f"relative difference {rel:.3e}"))
            elif not np.array_equal(x, y):
                bad.append((n, "integer or string values differ"))
    return bad


def counts(path):
    out = []
    with open(path, errors="replace") as f:
        for line in f:
            found = COUNT.findall(line)
            if found:
                out.append(tuple((k, int(v)) for k, v in found))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("before")
    ap.add_argument("after")
    ap.add_argument("--tol", type=float, default=1e-12, help="relative tolerance of real datasets")
    args = ap.parse_args()
    for d in (args.before, args.after):
        if not os.path.isdir(d):
            sys.exit(f"compare_outputs: no directory '{d}'")
    n_bad = n_files = 0
    for ext in (".h5", ".log"):
        fa, fb = files(args.before, ext), files(args.after, ext)
        for rel in sorted(fa ^ fb):
            print(f"only in {'before' if rel in fa else 'after'}: {rel}")
        for rel in sorted(fa & fb):
            n_files += 1
            pa, pb = os.path.join(args.before, rel), os.path.join(args.after, rel)
            if ext == ".h5":
                bad = compare_h5(pa, pb, args.tol)
                for n, msg in bad:
                    print(f"DIFF {rel}:{n}: {msg}")
            else:
                ca, cb = counts(pa), counts(pb)
                bad = [] if ca == cb else [1]
                if bad:
                    print(f"DIFF {rel}: iteration counts {ca[:6]}... vs {cb[:6]}...")
            n_bad += bool(bad)
    print(f"{n_files} files compared, {n_bad} differ (tolerance {args.tol:.1e})")
    sys.exit(1 if n_bad else 0)


if __name__ == "__main__":
    main()
