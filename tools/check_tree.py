#!/usr/bin/env python3
"""The project's structure check, run by `make test` (suite check_tree).

The Fortran sources live in layers, lowest first:

    modules/base  modules/bindings  modules/numerics
    src/config  src/discretization  src/io  src/physics  src/drivers

A module may use modules of its own layer and of lower layers, never of a
higher one. The check reads every .f90 file of those folders and fails when

  1. a module uses a project module of a higher layer;
  2. project modules use each other in a cycle;
  3. a procedure (subroutine or function, with the procedures it contains:
     they share its state by host association) is longer than --max-lines
     lines (default 150);
  4. a file defines no module and is not the main program, or a module is
     defined twice.

Modules that the tree does not define (mpi, hdf5, iso_c_binding, ...) are
outside the check. Tests (tests/) may use any layer.

usage: check_tree.py [--root DIR] [--max-lines N] [--list]
--list prints the layer of every module and the longest procedures.
Prints "suite check_tree: N passed, N failed" last; exits 1 on a failure.
"""
import argparse
import os
import re
import sys

LAYERS = [
    "modules/base",
    "modules/bindings",
    "modules/numerics",
    "src/config",
    "src/discretization",
    "src/io",
    "src/physics",
    "src/drivers",
]
MAIN_PROGRAM = "src/drivers/geoblock.f90"

RE_MODULE = re.compile(r"^\s*module\s+(\w+)\s*$", re.I)
RE_USE = re.compile(r"^\s*use\s*(?:,\s*(?:non_)?intrinsic\s*::)?\s*(?:::)?\s*(\w+)", re.I)
RE_PROGRAM = re.compile(r"^\s*program\s+(\w+)", re.I)
RE_PROC_START = re.compile(
    r"^\s*(?:(?:pure|elemental|recursive|impure|module|non_recursive)\s+|"
    r"(?:integer|real|logical|character|complex|type|class)\s*(?:\([^)]*\))?\s+)*"
    r"(subroutine|function)\s+(\w+)", re.I)
RE_PROC_END = re.compile(r"^\s*end\s*(subroutine|function)\b", re.I)
RE_INTERFACE = re.compile(r"^\s*(abstract\s+)?interface\b", re.I)
RE_END_INTERFACE = re.compile(r"^\s*end\s*interface\b", re.I)


def strip(line):
    """The code of a line without its comment (strings are rare enough in
    use and procedure statements to be ignored)."""
    i = line.find("!")
    return line if i < 0 else line[:i]


def scan(path):
    """Modules defined, modules used, procedures (name, first line, length
    including contained procedures)."""
    defined, used, procs = [], set(), []
    stack = []          # [name, start, own_lines]
    in_interface = 0
    with open(path, errors="replace") as f:
        lines = f.readlines()
    for no, raw in enumerate(lines, 1):
        line = strip(raw)
        m = RE_MODULE.match(line)
        if m and m.group(1).lower() != "procedure":
            defined.append(m.group(1).lower())
        m = RE_USE.match(line)
        if m:
            used.add(m.group(1).lower())
        if RE_INTERFACE.match(line):
            in_interface += 1
            continue
        if RE_END_INTERFACE.match(line):
            in_interface -= 1
            continue
        if in_interface:
            continue
        for entry in stack:
            entry[2] += 1
        if RE_PROC_END.match(line):
            if stack:
                name, start, own = stack.pop()
                procs.append((name, start, own))
            continue
        m = RE_PROC_START.match(line)
        if m and not re.match(r"^\s*end\b", line, re.I) and "procedure" not in line.lower().split("::")[0]:
            stack.append([m.group(2).lower(), no, 1])
    return defined, used, procs


def layer_of(rel):
    for i, layer in enumerate(LAYERS):
        if rel.startswith(layer + "/"):
            return i
    return None


def find_cycles(graph):
    """Strongly connected components with more than one module (Tarjan)."""
    index, low, on, stack, out = {}, {}, set(), [], []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1 or v in graph.get(v, ()):
                out.append(sorted(comp))

    sys.setrecursionlimit(10000)
    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--root", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    ap.add_argument("--max-lines", type=int, default=150)
    ap.add_argument("--list", action="store_true")
    args = ap.parse_args()
    root = os.path.abspath(args.root)

    files = []
    for top in ("modules", "src"):
        for base, _, names in os.walk(os.path.join(root, top)):
            for n in sorted(names):
                if n.endswith(".f90"):
                    files.append(os.path.relpath(os.path.join(base, n), root))
    files.sort()

    failures, passed = [], 0
    provider, info = {}, {}
    for rel in files:
        defined, used, procs = scan(os.path.join(root, rel))
        info[rel] = (defined, used, procs)
        layer = layer_of(rel)
        if layer is None:
            failures.append(f"{rel}: not in a layer folder ({', '.join(LAYERS)})")
            continue
        if not defined and rel != MAIN_PROGRAM:
            failures.append(f"{rel}: defines no module")
        for m in defined:
            if m in provider:
                failures.append(f"module {m} defined in {provider[m]} and {rel}")
            provider[m] = rel

    graph = {}
    n_uses = 0
    for rel in files:
        defined, used, procs = info[rel]
        layer = layer_of(rel)
        if layer is None:
            continue
        src_name = defined[0] if defined else os.path.basename(rel)[:-4]
        for u in sorted(used):
            if u not in provider:
                continue
            n_uses += 1
            target = provider[u]
            graph.setdefault(src_name, set()).add(u)
            if layer_of(target) > layer:
                failures.append(f"{rel} ({LAYERS[layer]}) uses {u} of a higher layer ({target})")
        for name, start, own in procs:
            if own > args.max_lines:
                failures.append(f"{rel}:{start}: procedure {name} has {own} lines (limit {args.max_lines})")

    cycles = find_cycles(graph)
    for c in cycles:
        failures.append("use cycle: " + " -> ".join(c))

    if args.list:
        for rel in files:
            defined = info[rel][0]
            lay = layer_of(rel)
            print(f"{LAYERS[lay] if lay is not None else '?':20s} {rel}")
        longest = sorted(((own, rel, name, start) for rel in files for name, start, own in info[rel][2]),
                         reverse=True)[:15]
        print("longest procedures:")
        for own, rel, name, start in longest:
            print(f"  {own:5d}  {rel}:{start} {name}")

    checks = [
        ("layers: no module uses a higher layer", not any("higher layer" in f for f in failures)),
        ("no use cycles", not cycles),
        (f"no procedure over {args.max_lines} lines", not any("procedure" in f and "lines" in f for f in failures)),
        ("every file is in a layer and defines its module once",
         not any(("not in a layer" in f) or ("defines no module" in f) or ("defined in" in f) for f in failures)),
    ]
    for f in failures:
        print("  FAIL  " + f)
    for what, good in checks:
        print(f"  {'ok  ' if good else 'FAIL'}  {what}")
        passed += good
    print(f"  {len(files)} files, {len(provider)} modules, {n_uses} uses between project modules")
    n_fail = len(checks) - passed
    print(f"suite check_tree: {passed} passed, {n_fail} failed")
    sys.exit(1 if n_fail else 0)


if __name__ == "__main__":
    main()
