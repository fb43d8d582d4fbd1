#!/usr/bin/env python3
"""The field case (input/hi24l_coupled.nml): read a run's output, per step
and per fault the slipping elements, their largest and mean slip, and the
matrix's pressure change of the produced compartment per sand.

Usage:
  field_coupled.py compartment RUN_STEM X,Y,Z [...] -o HISTORY_STEM
      the mean pressure change of each point's block (its cells of the
      point's region joined by faces not on a fault) at every output step;
      writes HISTORY_STEM_<k>.tab ('load factor  factor' rows, step n of N
      at n / N) and prints 'k value' lines: the one-way run's
      &pressure_change value (the last step's mean) of each point
  field_coupled.py faults RUN_STEM [--label NAME] [--times T0,T1,...]
      per step and fault: elements slipping (status 1), largest and mean
      slip magnitude over them [m]; a markdown table on stdout and a
      machine line per fault 'first FAULT STEP MAX MEAN' for the faults
      that slip at the last step
  field_coupled.py picture RUN_STEM STEP -o PNG [--sand REGION_ID]
      the slip on the faults (map view, element centres) and the matrix's
      pressure change in one sand (cell centres) at STEP
  field_coupled.py sign RUN_STEM STEP X,Y,Z
      the smoke test's check: in the point's block the matrix pressure
      fell, and on the fault elements beside that block (open exchange)
      the fracture pressure fell and the effective normal traction became
      more compressive (sigma_n' = t_N more negative) than at step 0;
      exit 1 otherwise
"""
import glob
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'tests', 'driver'))
from check_compartment import blocks, cell_of  # noqa: E402


def steps_of(stem):
    files = sorted(glob.glob(stem + '_[0-9][0-9][0-9][0-9].h5'))
    return [int(f[-7:-3]) for f in files]


def mesh_of(stem):
    with h5py.File(stem + '_mesh.h5', 'r') as m:
        return m['coords'][:], m['connectivity'][:]


def read(stem, step, name):
    with h5py.File('%s_%04d.h5' % (stem, step), 'r') as f:
        return f[name][:]


def block_cells(stem, point):
    x, conn = mesh_of(stem)
    region = read(stem, 0, 'region')
    root = blocks(conn, region)
    cand = cell_of(np.array(point), x, conn, region)
    if len(cand) == 0:
        sys.exit('field_coupled.py: point %s lies outside the mesh' % (point,))
    return np.nonzero(root == root[cand[0]])[0]


def compartment(args):
    stem = args[0]
    out = args[args.index('-o') + 1]
    points = [tuple(float(v) for v in a.split(',')) for a in args[1:args.index('-o')]]
    steps = steps_of(stem)
    last = steps[-1]
    for k, pt in enumerate(points, 1):
        cells = block_cells(stem, pt)
        means = [read(stem, s, 'pressure')[cells].mean() for s in steps]
        # step 0 (the in-situ equilibrium) is the reference
        dp = [m - means[0] for m in means]
        with open('%s_%d.tab' % (out, k), 'w') as h:
            h.write('# mean pressure change of the block of (%g, %g, %g): load factor, factor\n' % pt)
            for s, v in zip(steps, dp):
                h.write('%.6f %.9f\n' % (s / last, v / dp[-1] if dp[-1] != 0 else 0.0))
        print(k, '%.6e' % dp[-1], ' '.join('%.4e' % v for v in dp[1:]))


def fault_stats(stem, step):
    fault = read(stem, step, 'fractures/fault')
    status = read(stem, step, 'fractures/status')
    slip = read(stem, step, 'fractures/slip_magnitude')
    res = {}
    for f in np.unique(fault):
        m = (fault == f) & (status == 1)
        if m.any():
            res[int(f)] = (int(m.sum()), float(slip[m].max()), float(slip[m].mean()))
    return res


def faults(args):
    stem = args[0]
    label = args[args.index('--label') + 1] if '--label' in args else stem
    steps = [s for s in steps_of(stem) if s > 0]
    times = args[args.index('--times') + 1].split(',') if '--times' in args else [str(s) for s in steps]
    stats = {s: fault_stats(stem, s) for s in steps}
    names = sorted(set(f for s in steps for f in stats[s]))
    print('| %s: fault | ' % label + ' | '.join('step %d (%s)' % (s, t) for s, t in zip(steps, times)) + ' |')
    print('|---|' + '---|' * len(steps))
    for f in names:
        cells = []
        for s in steps:
            v = stats[s].get(f)
            cells.append('-' if v is None else '%d el., max %.3g m, mean %.3g m' % v)
        print('| f%02d | ' % f + ' | '.join(cells) + ' |')
    for f in names:
        first = next(s for s in steps if f in stats[s])
        v = stats[steps[-1]].get(f, (0, 0.0, 0.0))
        print('first f%02d %d %.4e %.4e' % (f, first, v[1], v[2]))


def picture(args):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    stem, step = args[0], int(args[1])
    png = args[args.index('-o') + 1]
    sand = int(args[args.index('--sand') + 1]) if '--sand' in args else None
    x, conn = mesh_of(stem)
    region = read(stem, 0, 'region')
    dp = read(stem, step, 'pressure') - read(stem, 0, 'pressure')
    centre = x[conn].mean(axis=1)
    if sand is None:  # the region with the largest depletion
        sand = int(region[np.argmin(dp)])
    c = read(stem, step, 'fractures/center')
    slip = read(stem, step, 'fractures/slip_magnitude')
    status = read(stem, step, 'fractures/status')
    fig, ax = plt.subplots(1, 2, figsize=(13, 5))
    m = region == sand
    sc = ax[0].scatter(centre[m, 0], centre[m, 1], c=dp[m] / 1e6, s=8, cmap='viridis', marker='s')
    fig.colorbar(sc, ax=ax[0], label='matrix pressure change [MPa]')
    ax[0].plot(c[:, 0], c[:, 1], ',', color='grey')
    ax[0].set_title('pressure change in region %d, step %d' % (sand, step))
    order = np.argsort(slip)
    sc = ax[1].scatter(c[order, 0], c[order, 1], c=slip[order], s=6, cmap='inferno_r')
    fig.colorbar(sc, ax=ax[1], label='slip magnitude [m]')
    sl = status == 1
    ax[1].scatter(c[sl, 0], c[sl, 1], s=18, facecolors='none', edgecolors='tab:blue', linewidths=0.6,
                  label='slipping')
    ax[1].legend(loc='upper right')
    ax[1].set_title('slip on the faults (map view), step %d' % step)
    for a in ax:
        a.set_aspect('equal')
        a.set_xlabel('x [m]')
        a.set_ylabel('y [m]')
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    print('picture:', png)


def sign(args):
    stem, step = args[0], int(args[1])
    pt = tuple(float(v) for v in args[2].split(','))
    cells = block_cells(stem, pt)
    dpm = read(stem, step, 'pressure')[cells] - read(stem, 0, 'pressure')[cells]
    x, conn = mesh_of(stem)
    # fault elements beside the block: a corner within the block's cells' nodes
    nodes = set(conn[cells].ravel().tolist())
    with h5py.File(stem + '_mesh.h5', 'r') as m:
        fx = m['fractures/coords'][:]
        fconn = m['fractures/connectivity'][:]
    xs = {tuple(np.round(v, 6)) for v in x[list(nodes)]}
    beside = np.array([any(tuple(np.round(fx[n], 6)) in xs for n in e) for e in fconn])
    dpf = read(stem, step, 'fractures/pressure') - read(stem, 0, 'fractures/pressure')
    dtn = read(stem, step, 'fractures/normal_traction') - read(stem, 0, 'fractures/normal_traction')
    ok = True
    print('block: %d cells, mean matrix pressure change %.4e Pa' % (len(cells), dpm.mean()))
    if not dpm.mean() < 0:
        ok = False
        print('FAIL: the produced block did not deplete')
    n = int(beside.sum())
    print('fault elements beside it: %d, mean fracture pressure change %.4e Pa, mean effective normal '
          'traction change %.4e Pa' % (n, dpf[beside].mean(), dtn[beside].mean()))
    if n == 0 or not dpf[beside].mean() < 0:
        ok = False
        print('FAIL: the fracture pressure beside the block did not fall')
    if n == 0 or not dtn[beside].mean() < 0:
        ok = False
        print('FAIL: the effective normal traction beside the block did not become more compressive')
    sys.exit(0 if ok else 1)


if __name__ == '__main__':
    if len(sys.argv) > 1 and sys.argv[1] in ('-h', '--help'):
        print(__doc__.replace('Usage:', 'usage:'))
        sys.exit(0)
    if len(sys.argv) < 3 or sys.argv[1] not in ('compartment', 'faults', 'picture', 'sign'):
        sys.exit(__doc__)
    {'compartment': compartment, 'faults': faults, 'picture': picture, 'sign': sign}[sys.argv[1]](sys.argv[2:])
