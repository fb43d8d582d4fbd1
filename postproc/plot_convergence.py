"""Plot the residual history of every linear solve of a geoblock run.

usage: /usr/bin/python3 postproc/plot_convergence.py [DIR] [PREFIX] [OUT.png]
Reads DIR/PREFIX_residuals.csv (step, time, iteration, relative residual),
written by the Biot driver; one curve per step."""
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def main():
    d = sys.argv[1] if len(sys.argv) > 1 else "out"
    prefix = sys.argv[2] if len(sys.argv) > 2 else "mandel"
    png = sys.argv[3] if len(sys.argv) > 3 else os.path.join(d, prefix + "_convergence.png")
    data = np.genfromtxt(os.path.join(d, prefix + "_residuals.csv"), delimiter=",", names=True)
    fig, ax = plt.subplots(figsize=(6, 4.2))
    steps = np.unique(data["step"]).astype(int)
    cmap = plt.get_cmap("viridis")
    for k, s in enumerate(steps):
        sel = data["step"] == s
        if sel.sum() < 2:
            continue
        ax.semilogy(data["iteration"][sel], data["relative_residual"][sel], "-", lw=0.8,
                    color=cmap(k / max(len(steps) - 1, 1)))
    ax.set_xlabel("FGMRES iteration")
    ax.set_ylabel("relative residual (scaled system)")
    ax.set_title(f"{prefix}: {len(steps)} solves (colour: step)")
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    print(png)


if __name__ == "__main__":
    main()
