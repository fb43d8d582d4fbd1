#!/usr/bin/env python3
"""The robustness matrix of the fluid in the fractures (issue 31).

One fracture with its tips inside a plane strain slab (one cell thick,
uz = 0 on both faces), 20 interface elements of size h, graded cells out to
a box 200 h wide; a well injecting at a constant rate into its middle
element; MUMPS. Every combination of

    residual aperture a0   1e-5, 1e-4, 1e-3, 1e-2 m
    element size h         1e-3, 1e-2, 1e-1, 1 m
    compressibility c_f    0, 1e-14, 1e-11, 1e-8 1/Pa
    time step dt           1e-3, 1, 1e3 s (three steps after step 0)
    fracture               closed (10 MPa in situ on both axes, the rate
                           fills it to 3 MPa in three steps) or open
                           (initial_state = 'open', no in-situ stress, the
                           rate opens it to about 1 MPa)
    ranks                  1, 2

must either run to the end (exit 0, every step reported) or be refused
before the first step with one error line that says why the problem is
singular (an incompressible fluid in a closed fracture). Anything else is a
failure: a crash, a step cut that ends the run, a hang (timeout).

Usage:
    matrix.py [--short | --full] [--out DIR] [--table FILE] [--jobs N]

--short (make test) runs a corner subset; --full (make bench) runs all 768.
Prints one line per case and ends with the suite's "N passed, N failed"
line; --table writes the matrix as Markdown (Newton iterations per step,
linear iterations, outcome).
"""
import argparse
import itertools
import os
import re
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
GEOBLOCK = os.environ.get('GEOBLOCK', os.path.join(ROOT, 'bin', 'geoblock'))
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT='1', OMPI_ALLOW_RUN_AS_ROOT_CONFIRM='1',
           OMPI_MCA_rmaps_base_oversubscribe='1', OMPI_MCA_odls_base_sigkill_timeout='0')

APERTURES = [1e-5, 1e-4, 1e-3, 1e-2]
SIZES = [1e-3, 1e-2, 1e-1, 1.0]
COMPRESSIBILITIES = [0.0, 1e-14, 1e-11, 1e-8]
STEPS = [1e-3, 1.0, 1e3]
STATES = ['closed', 'open']
RANKS = [1, 2]

YOUNG, POISSON, SIGMA = 1.0e10, 0.25, 1.0e7
N_ELEMENTS, N_STEPS = 20, 3


def rate(a0, h, cf, dt, state):
    """The injection rate [m^3/s] that raises a closed fracture's pressure
    to 3 MPa by its fluid's compressibility in N_STEPS steps, or opens an
    open one to about 1 MPa (Sneddon's plane strain crack volume)."""
    volume = N_ELEMENTS * h * h * a0
    if state == 'closed':
        return 3.0e6 * cf * volume / (N_STEPS * dt)
    b = 0.5 * N_ELEMENTS * h
    compliance = 2.0 * 3.141592653589793 * (1.0 - POISSON ** 2) * b * b * h / YOUNG
    return 1.0e6 * (compliance + cf * volume) / (N_STEPS * dt)


def deck(name, out, a0, h, cf, dt, state):
    """The deck of one case (lengths in units of h)."""
    half = 0.5 * N_ELEMENTS * h
    loads = ''
    if state == 'closed':
        loads = f"""&boundary
  set = 'xmin', type = 'displacement', ux = 0.0
/
&boundary
  set = 'ymin', type = 'displacement', uy = 0.0
/
&boundary
  set = 'xmax', type = 'traction', traction = {-SIGMA:.6e}, 0.0, 0.0
/
&boundary
  set = 'ymax', type = 'traction', traction = 0.0, {-SIGMA:.6e}, 0.0
/
"""
    else:
        for side in ('xmin', 'xmax', 'ymin', 'ymax'):
            loads += f"&boundary\n  set = '{side}', type = 'displacement', ux = 0.0, uy = 0.0\n/\n"
    initial = "\n  initial_state = 'open'" if state == 'open' else ''
    return f"""! robustness matrix case {name} (tests/robustness/matrix.py)
&run
  title = '{name}'
  physics = 'fracture_flow'
/
&mesh
  source = 'box'
  nx = 48, ny = 28, nz = 1
  lower = {-100 * h:.6e}, {-100 * h:.6e}, 0.0
  upper = {100 * h:.6e}, {100 * h:.6e}, {h:.6e}
  core_n = 24, 4
  core_lower = {-12 * h:.6e}, {-2 * h:.6e}
  core_upper = {12 * h:.6e}, {2 * h:.6e}
/
&fault
  name = 'crack'
  normal_axis = 'y'
  position = 0.0
  lower = {-half:.6e}, 0.0, {-h:.6e}
  upper = {half:.6e}, 0.0, {2 * h:.6e}
  friction_angle = 30.0{initial}
/
&material
  region = 'domain'
  young = {YOUNG:.6e}
  poisson = {POISSON}
/
&boundary
  set = 'zmin', type = 'displacement', uz = 0.0
/
&boundary
  set = 'zmax', type = 'displacement', uz = 0.0
/
{loads}&solver
  method = 'mumps'
/
&output
  dir = '{out}'
  prefix = '{name}'
/
&fracture_flow
  residual_aperture = {a0:.6e}
  compressibility = {cf:.6e}
/
&well
  name = 'w'
  point = {0.5 * h:.6e}, 0.0, {0.5 * h:.6e}
  rate = {rate(a0, h, cf, dt, state):.6e}
/
&time
  dt = {dt:.6e}, t_end = {N_STEPS * dt:.6e}
/
"""


STEP_LINE = re.compile(r'^time step (\d+) .* newton +(\d+) +linear its +(\d+)')


def run_case(case, out):
    """Run one case; returns (case, outcome, detail, newton per step, linear its per step, seconds)."""
    a0, h, cf, dt, state, np_ = case
    name = f"m_a{a0:.0e}_h{h:.0e}_c{cf:.0e}_dt{dt:.0e}_{state}_np{np_}".replace('+', '')
    path = os.path.join(out, name + '.nml')
    with open(path, 'w') as f:
        f.write(deck(name, out, a0, h, cf, dt, state))
    t0 = time.time()
    cmd = ['mpirun', '--oversubscribe', '-np', str(np_), GEOBLOCK, path]
    try:
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, stdin=subprocess.DEVNULL,
                           env=ENV, timeout=300, text=True)
    except subprocess.TimeoutExpired:
        return case, 'FAIL', 'timed out after 300 s', [], [], time.time() - t0
    secs = time.time() - t0
    lines = p.stdout.splitlines()
    errors = [ln for ln in p.stderr.splitlines() if ln.startswith('geoblock: error:')]
    steps = [STEP_LINE.match(ln) for ln in lines]
    steps = [m for m in steps if m]
    newton = [int(m.group(2)) for m in steps]
    linear = [int(m.group(3)) for m in steps]
    cuts = sum('cut in half' in ln for ln in p.stderr.splitlines())
    if p.returncode == 0 and len(steps) == N_STEPS + 1:
        return case, 'ran', f'{cuts} cut(s)' if cuts else '', newton, linear, secs
    if p.returncode == 2 and not steps and len(errors) == 1 and 'singular' in errors[0]:
        return case, 'refused', errors[0].replace('geoblock: error: ', ''), newton, linear, secs
    why = errors[0] if errors else (p.stderr.strip().splitlines() or ['no error line'])[-1]
    return case, 'FAIL', f'exit {p.returncode}, {len(steps)} step(s): {why}', newton, linear, secs


def cases(short):
    if not short:
        return list(itertools.product(APERTURES, SIZES, COMPRESSIBILITIES, STEPS, STATES, RANKS))
    # the corners of the parameter box, each state, and the two singular
    # refusals; one case on 2 ranks; the open fracture of a0 1e-5 m in 1 m
    # elements at dt 1000 s (its cubic-law Newton needs sub-steps of dt/64
    # at first, which grow back: it failed after 4 cuts before)
    picked = [(1e-5, 1e-3, 1e-14, 1e-3, 'closed', 1), (1e-2, 1.0, 1e-8, 1e3, 'closed', 1),
              (1e-5, 1.0, 1e-11, 1e3, 'closed', 1), (1e-2, 1e-3, 1e-14, 1e-3, 'closed', 1),
              (1e-5, 1e-3, 0.0, 1e-3, 'open', 1), (1e-2, 1.0, 1e-14, 1e3, 'open', 1),
              (1e-3, 1e-2, 1e-14, 1.0, 'open', 1), (1e-4, 1e-1, 1e-8, 1e-3, 'open', 1),
              (1e-3, 1e-2, 0.0, 1.0, 'closed', 1), (1e-3, 1e-2, 4.5e-10, 1.0, 'closed', 2),
              (1e-5, 1.0, 0.0, 1e3, 'open', 1)]
    return picked


def table(results, path):
    """The matrix as Markdown: one row per case."""
    with open(path, 'w') as f:
        f.write('Robustness matrix of the fluid in the fractures (tests/robustness/matrix.py --full): '
                'a plane strain fracture of 20 elements of size h, a well at a constant rate, MUMPS; '
                'Newton iterations and linear iterations (refinement steps of the direct solves) '
                'per step (step 0 first).\n\n')
        f.write('| a0 [m] | h [m] | c_f [1/Pa] | dt [s] | fracture | ranks | outcome | Newton per step '
                '| linear its per step | seconds |\n')
        f.write('|---|---|---|---|---|---|---|---|---|---|\n')
        for case, outcome, detail, newton, linear, secs in results:
            a0, h, cf, dt, state, np_ = case
            what = outcome if not detail else f'{outcome}: {detail}'
            f.write(f"| {a0:g} | {h:g} | {cf:g} | {dt:g} | {state} | {np_} | {what} | "
                    f"{' '.join(map(str, newton))} | {' '.join(map(str, linear))} | {secs:.1f} |\n")
        ran = sum(r[1] == 'ran' for r in results)
        refused = sum(r[1] == 'refused' for r in results)
        failed = sum(r[1] == 'FAIL' for r in results)
        most = max((max(r[3]) for r in results if r[3]), default=0)
        f.write(f'\n{len(results)} cases: {ran} ran to the end, {refused} refused before the first step as '
                f'singular, {failed} failed; the largest Newton count of a step: {most}.\n')


def main():
    ap = argparse.ArgumentParser()
    g = ap.add_mutually_exclusive_group()
    g.add_argument('--short', action='store_true', default=True)
    g.add_argument('--full', action='store_true')
    ap.add_argument('--out', default=os.path.join(ROOT, 'build', 'test-out', 'robustness_matrix'))
    ap.add_argument('--table')
    ap.add_argument('--jobs', type=int, default=1)
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    selected = cases(not args.full)
    with ThreadPoolExecutor(max_workers=args.jobs) as pool:
        results = list(pool.map(lambda c: run_case(c, args.out), selected))
    passed = failed = 0
    for case, outcome, detail, newton, linear, secs in results:
        a0, h, cf, dt, state, np_ = case
        label = f'a0 {a0:g} m, h {h:g} m, c_f {cf:g} 1/Pa, dt {dt:g} s, {state}, {np_} rank(s)'
        ok = outcome != 'FAIL'
        # a closed fracture holding an incompressible fluid must be refused,
        # every other case must run
        must_refuse = cf == 0.0 and state == 'closed'
        if ok and must_refuse != (outcome == 'refused'):
            ok = False
            detail = f'{outcome} where it must be ' + ('refused' if must_refuse else 'run') + f' ({detail})'
        newton_text = ' '.join(map(str, newton))
        print(f"  {'ok  ' if ok else 'FAIL'}  {label}: {outcome} {detail} (Newton {newton_text})".rstrip())
        passed += ok
        failed += not ok
    if args.table:
        table(results, args.table)
    print(f'suite robustness_matrix: {passed} passed, {failed} failed')
    return 0 if failed == 0 else 1


if __name__ == '__main__':
    sys.exit(main())
