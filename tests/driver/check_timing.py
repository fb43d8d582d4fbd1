#!/usr/bin/env python3
"""The timing summary of a geoblock log lists the preconditioner's set-up
components under 'preconditioner set-up' (indented lines), and they add up
to no more than that total: they are parts of it. Every line is the maximum
over the ranks taken by itself, so the parts' maxima may come from
different ranks: 5 % slack for that, and 1 ms per line for the rounding of
the printed seconds.

The block "peak memory rise by phase" that follows (MB by which each phase
raised the peak resident memory) must be there, each rise at most the peak
of the largest rank, and the indented parts of a line at most that line's
rise (1 MB a line of rounding).

Usage: check_timing.py LOG NAME [NAME ...]   (each NAME a component line's label)
Prints the components with their seconds; exit 1 on a missing label, a sum
above the total or a rise that does not fit."""
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
    peak_line = [l for l in lines[start:] if l.startswith('peak resident memory:')]
    try:
        rstart = next(i for i, l in enumerate(lines) if l.startswith('peak memory rise by phase'))
    except StopIteration:
        print('no peak memory rise block')
        return 1
    if not peak_line:
        print('no peak resident memory line')
        return 1
    peak = int(re.search(r'memory: (\d+) MB', peak_line[0]).group(1))
    rise = re.compile(r'^  ( *)(\S.*?)\s+([0-9]+)$')
    parent, parent_mb, child_sum, nchild = None, 0, 0, 0
    bad = []

    def close():
        if parent is not None and child_sum > parent_mb + nchild:
            bad.append(f'parts of {parent} rise {child_sum} MB, above its {parent_mb} MB')
    for line in lines[rstart + 1:]:
        m = rise.match(line)
        if not m:
            break
        mb = int(m.group(3))
        if mb > peak:
            bad.append(f'{m.group(2)} rises {mb} MB, above the peak {peak} MB')
        if m.group(1):
            child_sum += mb
            nchild += 1
        else:
            close()
            parent, parent_mb, child_sum, nchild = m.group(2), mb, 0, 0
    close()
    if bad:
        print('; '.join(bad))
        return 1
    print(', '.join(f'{k} {v:.3f} s' for k, v in parts.items()) + f' (set-up {total:.3f} s); peak {peak} MB')
    return 0


if __name__ == '__main__':
    sys.exit(main())
