#!/usr/bin/env python3
"""The timing summary of a geoblock log lists the preconditioner's set-up
components under 'preconditioner set-up' (indented lines), and they add up
to no more than that total: they are parts of it. Every line is the maximum
over the ranks taken by itself, so the parts' maxima may come from
different ranks: 5 % slack for that, and 1 ms per line for the rounding of
the printed seconds.

Usage: check_timing.py LOG NAME [NAME ...]   (each NAME a component line's label)
Prints the components with their seconds; exit 1 on a missing label or a sum
above the total."""
import re
import sys


def main():
    log, names = sys.argv[1], sys.argv[2:]
    lines = open(log).read().splitlines()
    try:
        start = next(i for i, l in enumerate(lines) if l.startswith('timing summary'))
    except StopIteration:
        print(f'no timing summary in {log}')
        return 1
    total, parts = None, {}
    row = re.compile(r'^  ( *)(\S.*?)\s+([0-9.]+)\s+([0-9]+) calls$')
    for line in lines[start + 1:]:
        m = row.match(line)
        if not m:
            break
        indent, label, secs = m.group(1), m.group(2), float(m.group(3))
        if label == 'preconditioner set-up':
            total = secs
        elif indent and total is not None:
            parts[label] = secs
    if total is None:
        print('no preconditioner set-up line')
        return 1
    missing = [n for n in names if n not in parts]
    if missing:
        print(f'components missing: {missing}; found {sorted(parts)}')
        return 1
    s = sum(parts.values())
    if s > 1.05 * total + 1e-3 * (len(parts) + 1):
        print(f'components sum to {s:.3f} s, above the set-up total {total:.3f} s')
        return 1
    print(', '.join(f'{k} {v:.3f} s' for k, v in parts.items()) + f' (set-up {total:.3f} s)')
    return 0


if __name__ == '__main__':
    sys.exit(main())
