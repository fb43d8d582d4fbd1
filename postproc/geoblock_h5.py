"""Read geoblock's output: HDF5/XDMF fields and the resolved deck.

A run with output prefix P in directory D writes D/P_mesh.h5 (coords,
connectivity), one D/P_NNNN.h5 per output time (fields, attribute 'time'),
D/P.xdmf (the index ParaView opens) and D/P_parameters.nml (every deck
variable the run used; read_parameters). Needs numpy and h5py (Debian
packages python3-numpy, python3-h5py).

script_main runs a postproc script's main() so that a missing or unreadable
file ends it with one line 'NAME: error: ...' on stderr and exit status 1,
not with a traceback.
"""
import glob
import os
import re
import sys

import h5py
import numpy as np


class Run:
    """The output of one run: mesh and the list of steps."""

    def __init__(self, directory, prefix):
        self.dir = directory
        self.prefix = prefix
        mesh = os.path.join(directory, prefix + "_mesh.h5")
        if not os.path.exists(mesh):
            raise FileNotFoundError(f"no geoblock mesh file {mesh} (is {directory} the output directory of a "
                                    f"run with prefix '{prefix}'?)")
        try:
            with h5py.File(mesh, "r") as f:
                self.coords = np.array(f["coords"])          # (n_nodes, 3)
                self.conn = np.array(f["connectivity"])      # (n_cells, 8), 0-based
        except (OSError, KeyError) as e:
            raise OSError(f"cannot read the mesh file {mesh}: {e}") from None
        pat = re.compile(re.escape(prefix) + r"_(\d{4,})\.h5$")
        steps = []
        for path in glob.glob(os.path.join(directory, prefix + "_*.h5")):
            m = pat.search(os.path.basename(path))
            if m:
                steps.append((int(m.group(1)), path))
        self.steps = [p for _, p in sorted(steps)]

    def times(self):
        out = []
        for p in self.steps:
            with h5py.File(p, "r") as f:
                out.append(float(f.attrs["time"]))
        return np.array(out)

    def field(self, name, step=-1):
        """Field array of a step (nodes or cells first, components second)."""
        with h5py.File(self.steps[step], "r") as f:
            return np.array(f[name])

    def cell_centres(self):
        return self.coords[self.conn].mean(axis=1)

    def fractures(self, required=True):
        """(coords, quads) of a contact run's fractures grid (one quad per
        interface element, 4 nodes of its own); None without one, or an
        error when required."""
        mesh = os.path.join(self.dir, self.prefix + "_mesh.h5")
        with h5py.File(mesh, "r") as f:
            if "fractures" not in f:
                if required:
                    raise ValueError(f"{os.path.join(self.dir, self.prefix)}: the run has no fractures grid "
                                     "(not a contact run?)")
                return None
            return np.array(f["fractures/coords"]), np.array(f["fractures/connectivity"])

    def parameters(self):
        """The run's resolved deck, D/P_parameters.nml (read_parameters)."""
        return read_parameters(os.path.join(self.dir, self.prefix + "_parameters.nml"))


_ASSIGN = re.compile(r"([A-Za-z_]\w*(?:\(\d+\))?)\s*=")


def _strip_comment(line):
    quote = None
    for i, ch in enumerate(line):
        if quote:
            if ch == quote:
                quote = None
        elif ch in "'\"":
            quote = ch
        elif ch == "!":
            return line[:i]
    return line


def _value(text):
    """A namelist value: a quoted string, a logical, a number or a list of them."""
    items = []
    for tok in re.findall(r"'(?:[^']|'')*'|\"[^\"]*\"|[^,\s]+", text):
        if tok[0] in "'\"":
            items.append(tok[1:-1].replace(tok[0] * 2, tok[0]))
        elif tok.lower() in (".true.", "t", ".t."):
            items.append(True)
        elif tok.lower() in (".false.", "f", ".f."):
            items.append(False)
        else:
            items.append(float(tok.lower().replace("d", "e")) if re.search(r"[.eEdD]", tok) else int(tok))
    return items[0] if len(items) == 1 else items


def read_parameters(path):
    """The groups of a geoblock deck (e.g. <prefix>_parameters.nml) as
    {group: [dict of variable -> value, one per occurrence]}: numbers as
    int or float, logicals as bool, strings unquoted, arrays as lists;
    'lower(2) = x' sets element 2 of list 'lower'. Raises OSError when the
    file cannot be read, ValueError when it is not a deck."""
    with open(path) as f:
        text = "\n".join(_strip_comment(line) for line in f)
    groups = {}
    for m in re.finditer(r"&(\w+)(.*?)(?<![^\s,])/", text, re.S):
        body = m.group(2)
        names = list(_ASSIGN.finditer(body))
        var = {}
        for i, a in enumerate(names):
            end = names[i + 1].start() if i + 1 < len(names) else len(body)
            name, value = a.group(1).lower(), _value(body[a.end():end].strip().rstrip(","))
            if "(" in name:
                base, k = name[:-1].split("(")
                lst = var.setdefault(base, [None] * 3)
                lst[int(k) - 1] = value
            else:
                var[name] = value
        groups.setdefault(m.group(1).lower(), []).append(var)
    if not groups:
        raise ValueError(f"{path}: no namelist group found")
    return groups


def script_main(main):
    """Run main() and exit with its status; a missing or unreadable file, or
    a value missing from it, ends the script with one line on stderr."""
    name = os.path.basename(sys.argv[0])
    try:
        status = main()
    except (OSError, ValueError, KeyError, IndexError) as e:
        what = f"missing value {e}" if isinstance(e, KeyError) else str(e)
        print(f"{name}: error: {what}", file=sys.stderr)
        sys.exit(1)
    sys.exit(status or 0)


def coordinate_order(points, decimals=9):
    """Permutation that sorts points lexicographically by rounded coordinates,
    so that runs with different partitions (and global numberings) compare."""
    p = np.round(np.asarray(points), decimals)
    return np.lexsort((p[:, 2], p[:, 1], p[:, 0]))


if __name__ == "__main__":
    import argparse
    ap = argparse.ArgumentParser(description="Read geoblock's output (a module for the other scripts); run as "
                                 "a script it lists a run's output steps and its resolved deck groups.")
    ap.add_argument("dir", help="output directory of the run")
    ap.add_argument("prefix", help="output prefix of the run")
    cli = ap.parse_args()

    def show():
        run = Run(cli.dir, cli.prefix)
        print(f"{len(run.steps)} output steps, times {run.times()}")
        for group, occurrences in run.parameters().items():
            for values in occurrences:
                print(f"&{group} {values}")

    script_main(show)
