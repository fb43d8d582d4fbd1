#!/usr/bin/env python3
"""Bytes a CG + BoomerAMG iteration moves, from a geoblock log written with
&amg print_level = 1, and the bandwidth the solve phase reached.

The model (8-byte reals, 4-byte integers: hypre 2.26 as Debian builds it,
HYPRE_Int of 4 bytes, and our CSR with 4-byte local columns):

- a CSR matrix pass reads 12 bytes a non-zero and 4 a row; a level
  matrix's pass in geoblock's cycle on single-precision values (&amg
  precision = 'single', with cycle_code 'geoblock' and l1-gs, relax types
  13/14) 8 bytes a non-zero (a float and its column);
- our CG (modules/numerics/cg.f90), per iteration: one product with our
  matrix, 21 vector passes (the copies into and out of hypre's vectors 5,
  r.z 2, the new direction 3, the product's in and out 2, p.Aq 2, the two
  updates 6, the norm 1);
- one V-cycle (a sweep down and one up, of the types hypre prints), on
  every level but the coarsest: a Gauss-Seidel or Jacobi sweep reads the
  level's matrix once and makes 4 vector passes (right side, iterate in and
  out, l1 norms), a symmetric one (types 6, 8) twice that; a Chebyshev sweep (hypre's relax type 16, degree 2, the
  diagonally scaled form of par_cheby.c) reads it twice (the residual and
  one product) and makes 22 vector passes; then the residual (the matrix
  once, 3 passes), the interpolation twice (restriction as a transposed
  product, then the correction), 3 vector passes on the next level (the
  restricted right side, its zero guess, the correction's read); the
  coarsest level's dense factor (rows^2 reals) once.

hypre prints the interpolation's entries per row to one decimal only
(avgW), so its non-zeros carry that rounding (under 5 % of P, under 1 % of
the total here). Caches are not modelled: the coarse levels fit in them, so
the measured rate is an upper bound of the memory traffic the solve needs.

Usage: solve_bytes.py LOG TRIAD_GBS   prints one markdown table row's cells:
iterations | solve s | s/it | our A MB | hierarchy MB | vectors MB | total MB | GB/s | share
       solve_bytes.py --check LOG     the parse against hypre's own sums: the
grid and operator complexities from the parsed levels against the ones hypre
prints, the levels against the log's BoomerAMG line; exit 1 if they differ
"""
import re
import sys


def parse(path):
    text = open(path, errors='replace').read()
    m = re.search(r'displacement dofs: (\d+), matrix non-zeros: (\d+)', text)
    if not m:
        raise SystemExit(f'solve_bytes.py: {path}: no "displacement dofs" line')
    n, nnz = int(m.group(1)), int(m.group(2))
    levels, interp = [], []
    section = None
    for line in text.splitlines():
        if line.startswith('Operator Matrix Information'):
            section = 'A'
            continue
        if line.startswith('Interpolation Matrix Information'):
            section = 'P'
            continue
        if 'Complexity' in line:
            section = None
            continue
        if section == 'A':
            f = line.split()
            if len(f) >= 3 and f[0].isdigit():
                levels.append((int(f[1]), int(f[2])))
        elif section == 'P':
            f = line.split()
            if len(f) >= 7 and f[0].isdigit() and f[2] == 'x':
                interp.append((int(f[1]), float(f[6])))
    if not levels:
        raise SystemExit(f'solve_bytes.py: {path}: no hypre set-up statistics (&amg print_level = 1?)')
    types = re.search(r'Type 0=Jac.*: +(\d+) +(\d+) +(\d+)', text)
    relax = (int(types.group(1)), int(types.group(2))) if types else (13, 14)
    params = text + run_parameters(text)
    single = (re.search(r"precision *= 'single'", params) is not None
              and re.search(r"cycle_code *= 'geoblock'", params) is not None and relax == (13, 14))
    step = re.search(r'iterations +(\d+) .* solve +([0-9.]+) s', text)
    if not step:
        raise SystemExit(f'solve_bytes.py: {path}: no step line with iterations and solve time')
    return n, nnz, levels, interp, int(step.group(1)), float(step.group(2)), relax, single


def run_parameters(text):
    """The run's parameters file (every deck variable with its value: the
    &output dir and prefix of the deck the log names), or '' when not found."""
    m = re.search(r'^deck: (\S+), ranks', text, re.M)
    try:
        deck = open(m.group(1)).read() if m else ''
    except OSError:
        return ''
    d = re.search(r"dir *= *'([^']*)'", deck)
    pre = re.search(r"prefix *= *'([^']*)'", deck)
    if not (d and pre):
        return ''
    try:
        return open(f'{d.group(1)}/{pre.group(1)}_parameters.nml').read()
    except OSError:
        return ''


def csr(nnz, rows, value_bytes=8):
    return (value_bytes + 4.0) * nnz + 4.0 * rows


def sweep(relax_type):
    """(matrix passes, vector passes) of one smoothing sweep of a hypre relax type."""
    if relax_type == 16:
        return 2, 22
    if relax_type in (6, 8):          # symmetric Gauss-Seidel: a forward and a backward pass
        return 2, 8
    return 1, 4


def model(n, nnz, levels, interp, relax=(13, 14), single=False):
    ours = csr(nnz, n)
    vectors = 21.0 * 8 * n
    hier = 0.0
    (m_down, v_down), (m_up, v_up) = sweep(relax[0]), sweep(relax[1])
    for l in range(len(levels) - 1):
        rows, entries = levels[l]
        p_rows, p_avg = interp[l] if l < len(interp) else (rows, 0.0)
        coarse = levels[l + 1][0]
        hier += (m_down + 1 + m_up) * csr(entries, rows, 4 if single else 8) + 2 * csr(p_rows * p_avg, p_rows)
        vectors += 8.0 * ((v_down + 3 + v_up + 4) * rows + 3 * coarse)
    hier += 8.0 * levels[-1][0] ** 2
    return ours, hier, vectors


def check(path):
    text = open(path, errors='replace').read()
    n, nnz, levels, interp, its, solve, relax, single = parse(path)
    grid = sum(r for r, _ in levels) / levels[0][0]
    oper = sum(e for _, e in levels) / levels[0][1]
    g = re.search(r'grid = ([0-9.]+)', text)
    o = re.search(r'operator = ([0-9.]+)', text)
    lv = re.search(r'BoomerAMG: (\d+) levels', text)
    ok = (g and o and lv and abs(grid - float(g.group(1))) < 1e-5 and abs(oper - float(o.group(1))) < 1e-5
          and int(lv.group(1)) == len(levels) and len(interp) == len(levels) - 1 and levels[0] == (n, nnz))
    print(f'levels {len(levels)}, grid complexity {grid:.6f} (hypre {g.group(1) if g else "?"}), '
          f'operator complexity {oper:.6f} (hypre {o.group(1) if o else "?"}), '
          f'interpolation levels {len(interp)}, level 0 {levels[0]} (log: {n}, {nnz})')
    return 0 if ok else 1


def main():
    if len(sys.argv) == 3 and sys.argv[1] == '--check':
        sys.exit(check(sys.argv[2]))
    if len(sys.argv) != 3:
        raise SystemExit(__doc__)
    n, nnz, levels, interp, its, solve, relax, single = parse(sys.argv[1])
    triad = float(sys.argv[2])
    ours, hier, vectors = model(n, nnz, levels, interp, relax, single)
    total = ours + hier + vectors
    rate = total * its / solve / 1e9 if solve > 0 else 0.0
    mb = 1e6
    print(f'{its} | {solve:.2f} | {solve / max(its, 1):.3f} | {ours / mb:.0f} | {hier / mb:.0f} | '
          f'{vectors / mb:.0f} | {total / mb:.0f} | {rate:.1f} | {100 * rate / triad:.0f} %')


if __name__ == '__main__':
    main()
