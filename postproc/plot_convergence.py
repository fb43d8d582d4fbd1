"""Plot the residual history of every linear solve of a geoblock run.

usage: /usr/bin/python3 postproc/plot_convergence.py [--step N] [DIR] [PREFIX] [OUT.png]
Reads DIR/PREFIX_residuals.csv (step, time, newton, iteration, relative
residual), written by every run; one curve per linear solve (a step's Newton
iterations each have one), coloured by step. With --step N only the solves of
step N, coloured by Newton iteration: the seed's "convergence profiles for
all the linear systems in one time step" (e.g. of a fracture_flow run).

       /usr/bin/python3 postproc/plot_convergence.py --compare OUT.png DIR/PREFIX[=LABEL] ...
draws the first linear solve of each run (of step --step, default the
first step with one) in one plot, labelled: preconditioners compared on one
system."""
import argparse
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from geoblock_h5 import script_main  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dir", nargs="?", default="out", help="output directory of the run (default out)")
    ap.add_argument("prefix", nargs="?", default="mandel", help="output prefix of the run (default mandel)")
    ap.add_argument("png", nargs="?", help="figure file (default DIR/PREFIX_convergence.png)")
    ap.add_argument("--step", type=int, help="only the linear solves of this step")
    ap.add_argument("--compare", nargs="+", metavar="ARG", help="OUT.png DIR/PREFIX[=LABEL] ...: the first "
                    "solve of each run in one plot")
    args = ap.parse_args()
    if args.compare:
        return compare(args.compare, args.step)
    d, prefix = args.dir, args.prefix
    png = args.png or os.path.join(d, prefix + "_convergence.png")
    csv = os.path.join(d, prefix + "_residuals.csv")
    if not os.path.isfile(csv):
        raise FileNotFoundError(f"no residual history {csv}")
    data = np.genfromtxt(csv, delimiter=",", names=True)
    if data.dtype.names is None or "relative_residual" not in data.dtype.names:
        raise ValueError(f"{csv} is not a geoblock residual history")
    fig, ax = plt.subplots(figsize=(6, 4.2))
    steps = np.unique(data["step"]).astype(int)
    if args.step is not None:
        if args.step not in steps:
            raise ValueError(f"step {args.step} has no Krylov solve in {csv} (steps {steps.min()} to {steps.max()})")
        steps = np.array([args.step])
    cmap = plt.get_cmap("viridis")
    newton = data["newton"] if "newton" in data.dtype.names else np.ones(len(data))
    n_solves = 0
    for k, s in enumerate(steps):
        its = np.unique(newton[data["step"] == s])
        for j, it in enumerate(its):
            sel = (data["step"] == s) & (newton == it)
            if sel.sum() < 2:
                continue
            n_solves += 1
            c = j / max(len(its) - 1, 1) if args.step is not None else k / max(len(steps) - 1, 1)
            ax.semilogy(data["iteration"][sel], data["relative_residual"][sel], "-", lw=0.8, color=cmap(c),
                        label=f"Newton {int(it)}" if args.step is not None else None)
    ax.set_xlabel("Krylov iteration")
    ax.set_ylabel("relative residual (scaled system)")
    if args.step is not None:
        ax.set_title(f"{prefix}: the {n_solves} linear systems of step {args.step}")
        ax.legend(fontsize=7)
    else:
        ax.set_title(f"{prefix}: {n_solves} solves in {len(steps)} steps (colour: step)")
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    print(png)


def read_history(csv):
    if not os.path.isfile(csv):
        raise FileNotFoundError(f"no residual history {csv}")
    data = np.genfromtxt(csv, delimiter=",", names=True)
    if data.dtype.names is None or "relative_residual" not in data.dtype.names:
        raise ValueError(f"{csv} is not a geoblock residual history")
    return data


def compare(items, step):
    """The first solve (of step `step`, or of the first step with a Krylov
    solve) of each run DIR/PREFIX[=LABEL] in one plot, written to items[0]."""
    png, runs = items[0], items[1:]
    if not png.endswith(".png") or not runs:
        raise ValueError("--compare OUT.png DIR/PREFIX[=LABEL] ...")
    fig, ax = plt.subplots(figsize=(6, 4.2))
    for run in runs:
        path, _, label = run.partition("=")
        data = read_history(path + "_residuals.csv")
        s = step
        if s is None:
            counts = [(data["step"] == k).sum() for k in np.unique(data["step"])]
            s = np.unique(data["step"])[int(np.argmax(np.array(counts) > 1))]
        sel = data["step"] == s
        if "newton" in data.dtype.names:
            sel &= data["newton"] == data["newton"][sel].min()
        if sel.sum() < 2:
            raise ValueError(f"{path}: step {s} has no Krylov solve")
        its = data["iteration"][sel]
        ax.semilogy(its, data["relative_residual"][sel], "-", lw=1.2,
                    label=f"{label or os.path.basename(path)}: {int(its.max())} iterations")
    ax.set_xlabel("Krylov iteration")
    ax.set_ylabel("relative residual (scaled system)")
    ax.set_title("FGMRES convergence, one system, several preconditioners")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(png, dpi=100)
    print(png)
    return 0


if __name__ == "__main__":
    script_main(main)
