#!/usr/bin/env python3
"""PETSc's PCFIELDSPLIT on a linear system exported by geoblock (&solver
export_step, export_newton), the peer of our block preconditioners (issue 15).

    peer_petsc.py [options] STEM

STEM is the export's path without its suffix, e.g. out/mandel_step2_newton1:
the files STEM_K.mtx (the matrix as our FGMRES sees it, D A D), STEM_rhs.mtx
(D b) and STEM_fields.mtx (the block of every row; its header names the
blocks in order, e.g. u,q,p). Runs serially or under mpirun (every rank reads
the files and keeps its rows).

The preconditioner is a nested Schur-complement fieldsplit in the export's
block order, the same order as our own block preconditioner: the first block
against the others, with the others' Schur complement approximated by
PETSc's 'selfp' (A11 - A10 diag(A00)^-1 A01, assembled), and so on down the
blocks; full factorization at every level. Each single block is solved by
one BoomerAMG V-cycle with our own default settings (HMIS, ext+i with at
most 6 entries, one aggressive level, strong threshold 0.5, the smoother
geoblock's physics takes (--smoother: l1-Gauss-Seidel in the rows' order;
Chebyshev for Biot's u, q, p, PETSc's faster one there); three functions
for the displacement,
whose rows come in whole nodes),
except the flux q and the traction t blocks (a mass matrix, a stabilization),
by Jacobi. Blocks given together with --group (e.g. pm,p: the matrix and
the fracture pressure of poromechanics with faults, one Schur complement
for both as in our preconditioner; the default when both are exported) are
one split, at the position of the first. Right-preconditioned FGMRES(restart) to the relative true residual
rtol from x = 0, as ours. These are the best settings found
(doc/benchmarks-history.md, "Peers on the same systems"); PETSC_OPTIONS in
the environment overrides any of them (e.g.
PETSC_OPTIONS='-pc_fieldsplit_schur_fact_type upper').

Prints one line: iterations, set-up, solve and total seconds, the true
relative residual, the peak resident memory of rank 0, and with --ours-setup
/ --ours-solve our times on the same system and the ratio. Exit 1 when PETSc
did not converge.
"""
import argparse
import os
import resource
import sys
import time

# Debian's petsc4py is found through PETSC_DIR (or the /usr/lib/petsc link of
# the -dev package): default to the real-valued 3.18 build of python3-petsc4py
os.environ.setdefault("PETSC_DIR", "/usr/lib/petscdir/petsc3.18/x86_64-linux-gnu-real")
sys.path.append(os.path.join(os.environ["PETSC_DIR"], "lib", "python3", "dist-packages"))
try:
    import numpy as np
    import petsc4py
    petsc4py.init(sys.argv[:1])
    from petsc4py import PETSc
except ImportError as exc:  # pragma: no cover - the message is the point
    sys.exit(f"peer_petsc.py: error: {exc} (Debian: apt-get install python3-petsc4py)")

AMG = {
    "pc_hypre_type": "boomeramg",
    "pc_hypre_boomeramg_coarsen_type": "HMIS",
    "pc_hypre_boomeramg_interp_type": "ext+i",
    "pc_hypre_boomeramg_P_max": "6",
    "pc_hypre_boomeramg_agg_nl": "1",
    "pc_hypre_boomeramg_agg_num_paths": "1",
    "pc_hypre_boomeramg_strong_threshold": "0.5",
    "pc_hypre_boomeramg_max_iter": "1",
}
# the smoothers as ours (modules/numerics/amg_params.f90): l1 Gauss-Seidel
# forward down, backward up, rows in their order (PETSc's default is the C/F
# order), or hypre's Chebyshev; the coarsest level by Gaussian elimination.
# Biot's systems (u, q, p) default to Chebyshev: geoblock's l1 Gauss-Seidel
# runs in its own cycle (amg_cycle.c), whose backward sweep reads memory
# downwards; PETSc's reaches hypre's own, whose backward sweep does not,
# and there Chebyshev was the faster of the two (Mandel at the seed's size,
# set-up + solve 0.81-0.95x, 2026-12-02), so the peer keeps its best.
SMOOTHERS = {
    "l1-gs": {"pc_hypre_boomeramg_relax_type_down": "l1-Gauss-Seidel",
              "pc_hypre_boomeramg_relax_type_up": "backward-l1-Gauss-Seidel",
              "pc_hypre_boomeramg_no_CF": "true"},
    "chebyshev": {"pc_hypre_boomeramg_relax_type_down": "Chebyshev",
                  "pc_hypre_boomeramg_relax_type_up": "Chebyshev"},
}
JACOBI_FIELDS = ("q", "t")


def fail(msg):
    sys.exit(f"peer_petsc.py: error: {msg}")


def read_mm(path):
    """A MatrixMarket file: ('coordinate', (rows, cols, vals), shape) or ('array', values, shape)."""
    try:
        fh = open(path)
    except OSError as exc:
        fail(f"cannot read {path}: {exc.strerror}")
    with fh:
        header = fh.readline().split()
        if len(header) < 4 or header[0] != "%%MatrixMarket":
            fail(f"{path} is not a MatrixMarket file")
        comments = []
        line = fh.readline()
        while line.startswith("%"):
            comments.append(line[1:].strip())
            line = fh.readline()
        dims = [int(v) for v in line.split()]
        data = np.loadtxt(fh, ndmin=2) if header[2] == "coordinate" else np.loadtxt(fh, ndmin=1)
    if header[2] == "coordinate":
        if data.shape[0] != dims[2]:
            fail(f"{path}: {data.shape[0]} entries, the header says {dims[2]}")
        return "coordinate", (data[:, 0].astype(np.int64) - 1, data[:, 1].astype(np.int64) - 1, data[:, 2]), dims, comments
    return "array", data.ravel(), dims, comments


def load(stem):
    _, (r, c, v), dims, _ = read_mm(stem + "_K.mtx")
    _, b, _, _ = read_mm(stem + "_rhs.mtx")
    _, blk, _, comments = read_mm(stem + "_fields.mtx")
    names = None
    for line in comments:
        if "blocks (1, 2, ...):" in line:
            names = [s.strip() for s in line.split(":", 1)[1].split(",")]
    if names is None:
        fail(f"{stem}_fields.mtx names no blocks (an export of an older geoblock?)")
    n = dims[0]
    if len(b) != n or len(blk) != n:
        fail(f"{stem}: matrix of {n} rows, rhs of {len(b)}, field map of {len(blk)}")
    return n, (r, c, v), b, blk.astype(np.int64), names


def group_blocks(blk, names, group):
    """Merge the blocks named in `group` into one, at the first one's place:
    (new block of every row, new names)."""
    if not group:
        return blk, names
    missing = [g for g in group if g not in names]
    if missing:
        fail(f"--group {','.join(group)}: no block {','.join(missing)} in the export's {','.join(names)}")
    first = min(names.index(g) for g in group)
    new_names, old_to_new = [], {}
    for i, name in enumerate(names):
        if name in group and i != first:
            continue
        old_to_new[i + 1] = len(new_names) + 1
        new_names.append("+".join(group) if i == first else name)
    for g in group:
        old_to_new[names.index(g) + 1] = old_to_new[first + 1]
    return np.vectorize(old_to_new.get)(blk).astype(np.int64), new_names


def build(n, coo, b, comm):
    r, c, v = coo
    mat = PETSc.Mat().create(comm=comm)
    mat.setSizes([[PETSc.DECIDE, n], [PETSc.DECIDE, n]])
    mat.setType("aij")
    mat.setUp()
    lo, hi = mat.getOwnershipRange()
    keep = (r >= lo) & (r < hi)
    order = np.lexsort((c[keep], r[keep]))
    rr, cc, vv = r[keep][order], c[keep][order], v[keep][order]
    indptr = np.zeros(hi - lo + 1, dtype=PETSc.IntType)
    np.add.at(indptr, rr - lo + 1, 1)
    indptr = np.cumsum(indptr).astype(PETSc.IntType)
    mat = PETSc.Mat().createAIJ([[hi - lo, n], [hi - lo, n]], csr=(indptr, cc.astype(PETSc.IntType), vv), comm=comm)
    mat.assemble()
    rhs = mat.createVecLeft()
    rhs.setArray(b[lo:hi])
    return mat, rhs, lo, hi


def split_level(pc, prefix, fields, names, blk, ranges, comm, opts):
    """Schur fieldsplit of pc over the blocks `fields`: the first block against
    the rest. blk: the block of every row of the level's matrix (whole, on
    every rank), ranges the rows each rank owns (this rank's: lo:hi).
    Returns the remaining blocks when they need a level of their own."""
    lo, hi = ranges[comm.getRank()], ranges[comm.getRank() + 1]
    head = blk[lo:hi] == fields[0]
    rows = np.arange(lo, hi)
    is0 = PETSc.IS().createGeneral(rows[head].astype(PETSc.IntType), comm=comm)
    is1 = PETSc.IS().createGeneral(rows[~head].astype(PETSc.IntType), comm=comm)
    counts = [int(np.sum(blk[ranges[r]:ranges[r + 1]] == fields[0])) for r in range(len(ranges) - 1)]
    if names[fields[0] - 1] == "u" and all(c % 3 == 0 for c in counts):
        # whole nodes of interleaved x, y, z on every rank: BoomerAMG gets
        # three functions, as ours (else PETSc's row split cuts a node)
        is0.setBlockSize(3)
    pc.setType("fieldsplit")
    opts[prefix + "pc_type"] = "fieldsplit"
    opts[prefix + "pc_fieldsplit_type"] = "schur"
    opts[prefix + "pc_fieldsplit_schur_fact_type"] = "full"
    opts[prefix + "pc_fieldsplit_schur_precondition"] = "selfp"
    pc.setFieldSplitIS(("0", is0), ("1", is1))
    single(prefix + "fieldsplit_0_", names[fields[0] - 1], opts)
    if len(fields) == 2:
        single(prefix + "fieldsplit_1_", names[fields[1] - 1], opts)
        return None
    # the Schur complement's preconditioner gets its own split once it exists
    opts[prefix + "fieldsplit_1_ksp_type"] = "preonly"
    opts[prefix + "fieldsplit_1_pc_type"] = "none"
    return fields[1:]


def single(prefix, name, opts):
    opts[prefix + "ksp_type"] = "preonly"
    if name in JACOBI_FIELDS:
        opts[prefix + "pc_type"] = "jacobi"
    else:
        opts[prefix + "pc_type"] = "hypre"
        for k, v in AMG.items():
            opts[prefix + k] = v


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("stem")
    ap.add_argument("--rtol", type=float, default=1e-8)
    ap.add_argument("--restart", type=int, default=100)
    ap.add_argument("--maxit", type=int, default=2000)
    ap.add_argument("--ours-setup", type=float, default=None, help="our set-up seconds on this system")
    ap.add_argument("--ours-solve", type=float, default=None, help="our solve seconds on this system")
    ap.add_argument("--ours-its", type=int, default=None, help="our iterations on this system")
    ap.add_argument("--group", default=None,
                    help="blocks to split together, comma separated ('pm,p' by default when both are exported; "
                         "'none': every block alone)")
    ap.add_argument("--smoother", choices=sorted(SMOOTHERS), default=None,
                    help="BoomerAMG's smoother (default: 'chebyshev' for u,q,p, hypre's faster there, "
                         "else 'l1-gs', geoblock's)")
    args = ap.parse_args()
    comm = PETSc.COMM_WORLD
    n, coo, b, blk, names = load(args.stem)
    smoother = args.smoother or ("chebyshev" if names == ["u", "q", "p"] else "l1-gs")
    AMG.update(SMOOTHERS[smoother])
    AMG["pc_hypre_boomeramg_relax_type_coarse"] = "Gaussian-elimination"
    group = args.group
    if group is None:
        group = "pm,p" if "pm" in names and "p" in names else "none"
    if group != "none":
        blk, names = group_blocks(blk, names, [g.strip() for g in group.split(",")])
    fields = sorted(set(blk.tolist()))
    if fields != list(range(1, len(names) + 1)):
        fail(f"{args.stem}_fields.mtx: blocks {fields} against the names {names}")
    mat, rhs, lo, hi = build(n, coo, b, comm)
    ksp = PETSc.KSP().create(comm=comm)
    ksp.setOperators(mat)
    ksp.setType("fgmres")
    ksp.setGMRESRestart(args.restart)
    ksp.setTolerances(rtol=args.rtol, atol=0.0, max_it=args.maxit)
    ksp.setNormType(PETSc.KSP.NormType.UNPRECONDITIONED)
    opts = {}
    db = PETSc.Options()
    t0 = time.perf_counter()
    pc = ksp.getPC()
    if len(fields) == 1:
        single("", names[0], opts)
        rest = None
    else:
        rest = split_level(pc, "", fields, names, blk, mat.getOwnershipRanges(), comm, opts)
    for k, v in opts.items():
        if not db.hasName(k):        # PETSC_OPTIONS in the environment wins
            db[k] = v
    ksp.setFromOptions()
    ksp.setUp()
    prefix, level_blk = "", blk
    while rest is not None:
        # the next level: the Schur complement's preconditioner over the
        # remaining blocks; its rows are theirs, in global order
        sub = pc.getFieldSplitSubKSP()[1]
        prefix += "fieldsplit_1_"
        level_blk = level_blk[np.isin(level_blk, rest)]
        spc = sub.getPC()
        more = {}
        rest_next = split_level(spc, prefix, rest, names, level_blk, spc.getOperators()[1].getOwnershipRanges(),
                                comm, more)
        for k, v in more.items():
            if not db.hasName(k) or k.endswith("_pc_type"):
                db[k] = v
        spc.setFromOptions()
        spc.setUp()
        pc, rest = spc, rest_next
    t_setup = time.perf_counter() - t0
    x = mat.createVecRight()
    t0 = time.perf_counter()
    ksp.solve(rhs, x)
    t_solve = time.perf_counter() - t0
    its = ksp.getIterationNumber()
    reason = ksp.getConvergedReason()
    r = rhs.duplicate()
    mat.mult(x, r)
    r.aypx(-1.0, rhs)
    rel = r.norm() / rhs.norm()
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    total = t_setup + t_solve
    line = (f"petsc fieldsplit ({','.join(names)}): {'converged' if reason > 0 else 'NOT converged (reason ' + str(reason) + ')'}"
            f", iterations {its}, setup {t_setup:.3f} s, solve {t_solve:.3f} s, total {total:.3f} s, "
            f"true rel. residual {rel:.2e}, peak memory {peak:.0f} MB (rank 0), ranks {comm.getSize()}, smoother {smoother}")
    if args.ours_setup is not None and args.ours_solve is not None:
        ours = args.ours_setup + args.ours_solve
        line += f"; ours {ours:.3f} s" + (f" in {args.ours_its} its" if args.ours_its else "") + \
                f": ratio ours / petsc {ours / total:.2f}"
    if comm.getRank() == 0:
        print(line)
    return 0 if reason > 0 and rel <= 10 * args.rtol else 1


if __name__ == "__main__":
    sys.exit(main())
